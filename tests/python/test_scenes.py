# scene() returns the CLI's `reproject scene` views bit for bit, and the true eyes score a warp.
import subprocess

import numpy as np
import pytest
from PIL import Image

import pfm
import reproject


def same_bits(a, b):
    a, b = np.asarray(a, np.float32), np.asarray(b, np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


@pytest.mark.parametrize("name", ["pole", "near"])
def test_scene_equals_the_cli(cli, tmp_path, name):
    completed = subprocess.run([cli, "scene", "--scene", name, "--width", "160", "--height", "90",
                                "--color-format", "pfm", "--out-dir", str(tmp_path)], capture_output=True, text=True)
    assert completed.returncode == 0, completed.stderr
    s = reproject.scene(name, 160, 90)
    for view, array in (("centre", s.color), ("left", s.left), ("right", s.right)):
        assert same_bits(array, pfm.read(tmp_path / f"{view}.pfm")), view
    for view, array in (("centre", s.depth), ("left", s.left_depth), ("right", s.right_depth)):
        assert same_bits(array, pfm.read(tmp_path / f"{view}_depth.pfm")), view
    for eye, mask in (("left", s.left_visible), ("right", s.right_visible)):
        assert np.array_equal(mask, np.asarray(Image.open(tmp_path / f"{eye}_visible.png")) == 255), eye


def test_scene_fields_and_errors():
    s = reproject.scene("room", 192, 108, encoding="reversed")
    assert s.color.shape == (108, 192, 3) and s.depth.shape == (108, 192) and s.left_visible.dtype == bool
    assert s.decoder.encoding == "reversed" and (s.near, s.far) == (1.0, 20.0)
    assert (s.camera.separation, s.camera.convergence) == (0.03, 3.5)
    assert set(reproject.scenes) == {"room", "boxes", "pole", "spheres", "near", "edge"}
    with pytest.raises(ValueError, match="unknown scene 'kitchen'"):
        reproject.scene("kitchen", 64, 64)
    with pytest.raises(ValueError, match="not in 1..16384"):
        reproject.scene("room", 0, 64)


def test_exact_beats_not_moving_on_every_scene():
    for name in reproject.scenes:
        s = reproject.scene(name, 240, 135)
        r = reproject.warp(s.color, s.depth, decoder=s.decoder, separation=s.camera.separation,
                           convergence=s.camera.convergence, direction="centre-to-left")
        mask = s.left_visible
        warped = np.mean((r.color - s.left)[mask] ** 2)
        unmoved = np.mean((s.color - s.left)[mask] ** 2)
        print(f"{name}: PSNR {10 * np.log10(1 / warped):.2f} dB (not moved: {10 * np.log10(1 / unmoved):.2f} dB)")
        assert warped < unmoved / 4
