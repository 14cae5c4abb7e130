# examples/compare_methods.py runs on the teddy pair: one line per method and an anaglyph.
import pathlib
import re
import subprocess
import sys

import numpy as np
from PIL import Image

EXAMPLE = pathlib.Path(__file__).parents[2] / "examples" / "compare_methods.py"


def test_compare_methods_example(tmp_path):
    anaglyph = tmp_path / "anaglyph.png"
    completed = subprocess.run([sys.executable, str(EXAMPLE), "--anaglyph", str(anaglyph), "--repeats", "2"],
                               capture_output=True, text=True)
    print(completed.stdout, completed.stderr)
    assert completed.returncode == 0
    lines = {line.split()[0]: line for line in completed.stdout.splitlines()}
    for method in ("scanline", "march16", "single", "secant", "exact"):
        assert re.match(rf"{method}\s+PSNR\s+\d+\.\d\d dB\s+\d+\.\d\d ms", lines[method]), completed.stdout
    image = np.asarray(Image.open(anaglyph))
    assert image.shape == (375, 450, 3) and image.dtype == np.uint8
