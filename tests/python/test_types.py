# mypy (Debian's `mypy`) against the package's stubs: the examples and the typed calls pass
# (pyproject.toml's [tool.mypy], strict), and calls the stubs must refuse are refused, which shows
# that mypy reads the package's types (a package it could not type would be Any, and pass).
import os
import pathlib
import subprocess
import sys

import pytest

import reproject

ROOT = pathlib.Path(__file__).resolve().parents[2]
PACKAGE = pathlib.Path(reproject.__file__).resolve().parent

pytest.importorskip("mypy", reason="mypy is not installed for this interpreter (Debian: mypy)")


def mypy(tmp_path, *arguments):
    # mypy reads an installed package from the interpreter's site-packages (PEP 561: py.typed); the
    # build tree's (PYTHONPATH=build/python) through MYPYPATH. It imports nothing, so it needs
    # no sanitizer runtime either.
    env = {k: v for k, v in os.environ.items() if k not in ("LD_PRELOAD", "MYPYPATH", "PYTHONPATH")}
    if not any(part in ("site-packages", "dist-packages") for part in PACKAGE.parts):
        env["MYPYPATH"] = str(PACKAGE.parent)
    return subprocess.run([sys.executable, "-m", "mypy", "--python-executable", sys.executable, "--config-file",
                           str(ROOT / "pyproject.toml"), "--cache-dir", str(tmp_path / "cache"), *arguments],
                          cwd=ROOT, env=env, capture_output=True, text=True)


def test_mypy_passes_on_the_examples_and_the_typed_calls(tmp_path):
    completed = mypy(tmp_path)
    print(completed.stdout, completed.stderr)
    assert completed.returncode == 0
    assert completed.stdout.startswith("Success: no issues found in 3 source files")


def test_mypy_refuses_what_the_stubs_refuse(tmp_path):
    wrong = tmp_path / "wrong.py"
    wrong.write_text(
        "import reproject, reproject.metrics\n"
        "s = reproject.scene('room', 64, 32)\n"
        "reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, method='fast')\n"
        "reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, hole_fill='grey')\n"
        "reproject.warp_pair(s.color, s.depth, convergnce=3.5)\n"
        "reproject.Decoder.from_near_far('log', 1.0, 20.0)\n"
        "n: int = reproject.metrics.ssim(s.color, s.right)\n"
        "reproject.warp([[0.0]], s.depth)\n")
    completed = mypy(tmp_path, str(wrong))
    print(completed.stdout, completed.stderr)
    errors = [line for line in completed.stdout.splitlines() if ": error: " in line]
    assert [int(line.split(":")[1]) for line in errors] == [3, 4, 5, 6, 7, 8], errors
    assert "Literal['scanline', 'march16', 'single', 'secant', 'exact']" in errors[0]
    assert 'did you mean "convergence"' in errors[2]
