# README.md's Python example (its ```python block) runs as written, in a fresh interpreter.
import pathlib
import re
import subprocess
import sys

README = pathlib.Path(__file__).parents[2] / "README.md"


def test_readme_python_example_runs():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
    assert blocks, "README.md has no ```python block"
    code = blocks[0]
    assert len(code.strip().splitlines()) <= 5, "the README promises a five-line example"
    completed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    print(completed.stdout, completed.stderr)
    assert completed.returncode == 0
    assert re.match(r"secant: PSNR \d+\.\d\d dB, holes", completed.stdout)
