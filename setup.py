"""Builds the Python package's extension module, reproject._reproject, with CMake.

pyproject.toml holds the package's metadata; this file adds what setuptools cannot say there: the
version, read from the top-level CMakeLists.txt (written once, there), and a build_ext that
configures the CMake project with the library and the module alone (no tests, tools, benchmarks or
examples) and copies the module into the package. CMAKE_ARGS (extra -D options, e.g.
-DREPROJECT_SIMD=OFF) and CMAKE_BUILD_PARALLEL_LEVEL (jobs; default: all processors) are read from
the environment.
"""
import os
import pathlib
import re
import shlex
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def cmake_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(\s*reproject\s+VERSION\s+([0-9.]+)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt: no project(reproject VERSION ...) to read the version from")
    return match.group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = pathlib.Path(self.build_temp).resolve() / "cmake"
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            f"-DPython3_EXECUTABLE={sys.executable}",
            "-DREPROJECT_BUILD_PYTHON=ON", "-DREPROJECT_PYTHON_REQUIRED=ON",
            "-DREPROJECT_BUILD_TESTS=OFF", "-DREPROJECT_BUILD_TOOLS=OFF",
            "-DREPROJECT_BUILD_BENCHMARKS=OFF", "-DREPROJECT_BUILD_EXAMPLES=OFF",
            "-DREPROJECT_INSTALL=OFF",
        ] + shlex.split(os.environ.get("CMAKE_ARGS", ""))
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "reproject_python", "-j", jobs], check=True)
        # CMake names the module for the interpreter it was configured with, sys.executable.
        built = build_dir / "python" / "reproject" / ("_reproject" + sysconfig.get_config_var("EXT_SUFFIX"))
        if not built.is_file():
            raise RuntimeError(f"CMake built no {built}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        self.copy_file(str(built), str(target))


setup(
    version=cmake_version(),
    ext_modules=[Extension("reproject._reproject", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # setuptools' own build directory, apart from CMake's usual build/.
    options={"build": {"build_base": "build-python"}, "egg_info": {"egg_base": "build-python"}},
)
