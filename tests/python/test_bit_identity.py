# The module's results equal the C++ API's bit for bit: the command-line tool (the C++ API behind
# a file interface) is run on the same frames, written as PFM (exact floats), with the same
# instruction set named on both sides, and every output is compared bit for bit (NaN included).
import subprocess

import numpy as np
import pytest
from PIL import Image

import pfm
import reproject
import teddy

ARCH = reproject.selected_arch()


def same_bits(a, b):
    a, b = np.asarray(a, np.float32), np.asarray(b, np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


@pytest.fixture(scope="module")
def room(tmp_path_factory):
    s = reproject.scene("room", 320, 180)
    directory = tmp_path_factory.mktemp("room")
    pfm.write(directory / "color.pfm", s.color)
    pfm.write(directory / "depth.pfm", s.depth)
    return s, directory


def run(cli, *args):
    completed = subprocess.run([cli, *map(str, args)], capture_output=True, text=True)
    assert completed.returncode == 0, completed.stderr


@pytest.mark.parametrize("method", reproject.methods)
def test_warp_equals_the_cli(cli, room, method):
    s, d = room
    out = d / method
    out.mkdir()
    run(cli, "warp", "--color", d / "color.pfm", "--depth", d / "depth.pfm", "--encoding", "standard",
        "--near", s.near, "--far", s.far, "--separation", "0.03", "--convergence", "3.5",
        "--direction", "centre-to-right", "--method", method, "--arch", ARCH,
        "--out", out / "color.pfm", "--out-depth", out / "depth.pfm", "--status", out / "status.png",
        "--source-x", out / "source_x.pfm")
    r = reproject.warp(s.color, s.depth, encoding="standard", near=s.near, far=s.far, separation=0.03,
                       convergence=3.5, direction="centre-to-right", method=method, arch=ARCH)
    assert same_bits(r.color, pfm.read(out / "color.pfm"))
    assert same_bits(r.depth, pfm.read(out / "depth.pfm"))
    assert same_bits(r.source_x, pfm.read(out / "source_x.pfm"))
    assert np.array_equal(r.status, np.asarray(Image.open(out / "status.png")))
    print(f"{method}: colour, depth, source x and status equal the CLI's bit for bit ({ARCH})")


def test_pair_equals_the_cli(cli, room):
    s, d = room
    out = d / "pair"
    out.mkdir()
    run(cli, "pair", "--color", d / "color.pfm", "--depth", d / "depth.pfm", "--encoding", "standard",
        "--near", s.near, "--far", s.far, "--separation", "0.03", "--convergence", "3.5", "--method", "secant",
        "--arch", ARCH, "--out-left", out / "left.pfm", "--out-right", out / "right.pfm",
        "--out-left-depth", out / "left_depth.pfm", "--out-right-depth", out / "right_depth.pfm")
    left, right = reproject.warp_pair(s.color, s.depth, decoder=s.decoder, separation=0.03, convergence=3.5,
                                      method="secant", arch=ARCH)
    assert same_bits(left.color, pfm.read(out / "left.pfm"))
    assert same_bits(right.color, pfm.read(out / "right.pfm"))
    assert same_bits(left.depth, pfm.read(out / "left_depth.pfm"))
    assert same_bits(right.depth, pfm.read(out / "right_depth.pfm"))


@pytest.mark.parametrize("method", ["scanline", "single", "exact"])
def test_teddy_disparity_equals_the_cli(cli, data_dir, tmp_path, method):
    left, _, disp_left, _ = teddy.load(data_dir)
    color = left.astype(np.float32) / np.float32(255)
    disparity = teddy.fill_unknown(disp_left)
    pfm.write(tmp_path / "color.pfm", color)
    pfm.write(tmp_path / "disparity.pfm", disparity)
    run(cli, "warp", "--color", tmp_path / "color.pfm", "--depth", tmp_path / "disparity.pfm",
        "--disparity", "--method", method, "--arch", ARCH, "--out", tmp_path / "right.pfm",
        "--source-x", tmp_path / "source_x.pfm")
    r = reproject.warp(color, disparity, encoding="disparity", method=method, arch=ARCH)
    assert same_bits(r.color, pfm.read(tmp_path / "right.pfm"))
    assert same_bits(r.source_x, pfm.read(tmp_path / "source_x.pfm"))
