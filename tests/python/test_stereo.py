# The stereo helpers of stereo.hpp from Python, checked against what their definitions say.
import math

import numpy as np
import pytest

import reproject


@pytest.fixture(scope="module")
def room():
    return reproject.scene("room", 240, 135)


def test_parallax_budget(room):
    camera = reproject.StereoCamera(0.03, 3.5)
    b = reproject.parallax_budget(room.depth, room.decoder, camera, histogram_bins=16)
    z = room.decoder.linear_depth(room.depth).astype(np.float64)
    p = 0.03 * 240 * (1 - 3.5 / z)  # left -> right parallax, display pixels
    assert b.pixels == 240 * 135 and b.unreadable == 0
    assert b.min == pytest.approx(p.min(), rel=1e-5) and b.max == pytest.approx(p.max(), rel=1e-5)
    assert b.percentile[3] == pytest.approx(np.median(p), rel=1e-4)
    assert len(b.percentile) == len(reproject.budget_percentiles) == 7
    assert b.histogram.dtype == np.int64 and b.histogram.sum() + b.below_histogram + b.above_histogram == b.pixels
    assert reproject.parallax_budget(room.depth, room.decoder, camera).histogram is None
    with pytest.raises(ValueError):
        reproject.parallax_budget(room.depth, room.decoder, camera, histogram_bins=4, histogram_min=1.0)


def test_stereo_culling_frustum():
    mono = reproject.ViewFrustum.perspective(math.radians(60), 1920, 1080, 0.5, 100)
    camera = reproject.StereoCamera(0.03, 3.5)
    c = reproject.stereo_culling_frustum(mono, camera)
    assert c.pull_back == pytest.approx(0.03 * 3.5 / 1.03)
    assert c.planes.shape == (6, 4)
    assert c.contains(0, 0, 10) and not c.contains(0, 0, 1000)
    with pytest.raises(ValueError):
        reproject.stereo_culling_frustum(reproject.ViewFrustum(orthographic=True), camera)


def test_pick(room):
    left_to_right = room.camera.parallax(240, "left-to-right")
    r = reproject.pick(room.left_depth, room.right_depth, room.decoder, left_to_right, 120.0, 100)
    truth = room.decoder.linear_depth(room.depth[100, 120])
    assert r.source == "both"
    assert r.depth == pytest.approx(truth, rel=0.05)
    assert r.right_x - r.left_x == pytest.approx(r.parallax)


def test_screen_to_view(room):
    frustum = reproject.ViewFrustum.perspective(math.radians(60), 240, 135, room.near, room.far)
    s = reproject.make_screen_to_view(frustum, "standard", 240, 135)
    x, y, z = reproject.screen_to_view(s, room.depth)
    np.testing.assert_allclose(z, room.decoder.linear_depth(room.depth), rtol=1e-5)
    assert (x[50, 7], y[50, 7], z[50, 7]) == s.at_pixel(7, 50, room.depth[50, 7])
    with pytest.raises(ValueError):
        reproject.make_screen_to_view(frustum, "disparity", 240, 135)


def test_place_at_depth(room):
    camera = reproject.StereoCamera(0.03, 3.5)
    left, right = reproject.place_at_depth(0.1, -0.2, 7.0, camera, room.decoder)
    assert right[0] - left[0] == pytest.approx(2 * 0.03 * (1 - 3.5 / 7.0), rel=1e-6)
    assert left[1] == right[1] == pytest.approx(-0.2)
    assert left[2] == pytest.approx(room.decoder.encode(7.0))
    with pytest.raises(ValueError):
        reproject.place_at_depth(0, 0, 1.0, camera, reproject.Decoder.disparity())


def test_dilate_nearer_depth(room):
    radius = 3
    out = reproject.dilate_nearer_depth(room.depth, room.decoder, radius)
    # Standard depth grows with distance: the nearest in the window is the smallest stored value.
    padded = np.pad(room.depth, ((0, 0), (radius, radius)), constant_values=np.inf)
    windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * radius + 1, axis=1)
    assert np.array_equal(out, windows.min(axis=2))
    again = np.empty_like(out)
    assert reproject.dilate_nearer_depth(room.depth, room.decoder, radius, out=again) is again
    with pytest.raises(ValueError):
        reproject.dilate_nearer_depth(room.depth, room.decoder, -1)


def test_a_renderers_rig_and_relative_inverse_depth():
    # Blender's defaults: interocular 0.065, convergence 1.95, a 50 mm lens on a 36 mm sensor.
    fov = 2 * math.atan(18 / 50)
    rig = reproject.StereoCamera.from_rig(0.065, 1.95, fov)
    assert rig.separation == pytest.approx(0.065 / (2 * 1.95 * 0.36), rel=1e-12) and rig.convergence == 1.95
    assert rig.eye_translation(fov) == pytest.approx(0.0325, rel=1e-12)
    with pytest.raises(ValueError, match="horizontal_fov in \\(0, pi\\)"):
        reproject.StereoCamera.from_rig(0.065, 1.95, math.pi)
    # Relative inverse depth, decoded as w = v: 4 % of 1000 px from v = 0 to 1, zero at v = 0.25.
    model = reproject.ParallaxModel.from_relative(0.04, 0.25, 1000, "left-to-right")
    v = np.array([0.0, 0.25, 1.0], np.float32)
    assert model.parallax(reproject.Decoder.disparity().inverse_depth(v)).tolist() == [10.0, 0.0, -30.0]
    with pytest.raises(ValueError, match="zero-parallax plane must be in 0..1"):
        reproject.ParallaxModel.from_relative(0.04, 1.25, 1000, "left-to-right")
