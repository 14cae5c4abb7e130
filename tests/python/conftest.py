# Shared by the Python tests: where the data and the CLI are. The package under test is whichever
# `import reproject` finds: ctest sets PYTHONPATH to the build's python/ directory (the package
# build/python/reproject) and REPROJECT_TEST_DATA / REPROJECT_CLI (tests/python/CMakeLists.txt);
# CI also runs these files with the python of a venv the wheel was installed into, without
# PYTHONPATH (.ci/run). Run by hand, set the same.
import os
import pathlib

import pytest


@pytest.fixture(scope="session")
def data_dir():
    return pathlib.Path(os.environ.get("REPROJECT_TEST_DATA", pathlib.Path(__file__).parents[1] / "data"))


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("REPROJECT_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("REPROJECT_CLI is not set: the command-line tool was not built")
    return path
