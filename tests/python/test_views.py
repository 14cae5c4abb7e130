# Arrays reach the library as views: crops, row steps and every colour form work in place and give
# what a contiguous copy gives; what the library cannot view (a column step, a transpose) raises a
# clear ValueError and never reads the wrong memory. CI runs this file under AddressSanitizer too
# (the sanitizer build), so a read outside an array's memory fails it.
import numpy as np
import pytest

import reproject

H, W = 64, 96
KW = dict(encoding="standard", near=1.0, far=20.0, separation=0.03, convergence=3.5)


def frame(height=H, width=W, channels=3, seed=1):
    rng = np.random.default_rng(seed)
    color = rng.random((height, width, channels), dtype=np.float32)
    z = 2.0 + 10.0 * rng.random((height, 1)) + np.linspace(0, 2, width)[None, :]
    z[height // 4: height // 2, width // 3: width // 2] = 2.5  # a near box: holes and walls
    depth = ((1.0 / 1.0 - 1.0 / z) / (1.0 / 1.0 - 1.0 / 20.0)).astype(np.float32)
    return color, depth


def same(a, b):
    return np.array_equal(np.asarray(a).view(np.uint8), np.asarray(b).view(np.uint8)) if a.dtype == b.dtype else False


def assert_same_result(r, q):
    for field in ("color", "depth", "status", "source_x"):
        assert np.array_equal(getattr(r, field), getattr(q, field), equal_nan=field != "status"), field


@pytest.mark.parametrize("method", reproject.methods)
def test_crop_at_the_end_of_a_buffer(method):
    # The crop's last row ends where the parent's memory ends: a read past a row would leave it.
    color, depth = frame(H + 7, W + 13)
    crop_c, crop_d = color[7:, 13:], depth[7:, 13:]
    r = reproject.warp(crop_c, crop_d, method=method, **KW)
    q = reproject.warp(np.ascontiguousarray(crop_c), np.ascontiguousarray(crop_d), method=method, **KW)
    assert_same_result(r, q)


def test_row_step_is_a_view():
    color, depth = frame(2 * H, W)
    planes = np.ascontiguousarray(np.moveaxis(color, -1, 0))  # (C, H, W)
    r = reproject.warp(planes[:, ::2], depth[::2], **KW)
    q = reproject.warp(np.ascontiguousarray(planes[:, ::2]), np.ascontiguousarray(depth[::2]), **KW)
    assert_same_result(r, q)


ARCHES = [a for a in reproject.arches if reproject.arch_supported(a)]


@pytest.mark.parametrize("arch", ARCHES)
@pytest.mark.parametrize("channels", [1, 2, 3, 4])
def test_every_color_form_gives_the_same_pixels(channels, arch):
    color, depth = frame(channels=channels)
    reference = reproject.warp(np.ascontiguousarray(np.moveaxis(color, -1, 0)), depth, arch=arch, **KW)  # planes
    assert reference.color.shape == (channels, H, W)
    packed = reproject.warp(color, depth, arch=arch, **KW)  # (H, W, C): RGBA in place, else copied into planes
    assert packed.color.shape == (H, W, channels)
    # Bit for bit on every arch (AVX-512 planar colour once blended unfused: issue 10).
    assert np.array_equal(np.moveaxis(packed.color, -1, 0), reference.color)
    if channels == 1:
        plane = reproject.warp(color[:, :, 0], depth, arch=arch, **KW)
        assert np.array_equal(plane.color, reference.color[0])


def test_views_the_library_cannot_take_are_refused():
    color, depth = frame()
    planes = np.ascontiguousarray(np.moveaxis(color, -1, 0))
    with pytest.raises(ValueError, match=r"depth: float32 array of shape \(64, 48\).*columns are not consecutive"):
        reproject.warp(color[:, ::2], depth[:, ::2], **KW)
    with pytest.raises(ValueError, match="color: .*columns are not consecutive"):
        reproject.warp(planes[:, :, ::2], np.ascontiguousarray(depth[:, ::2]), **KW)
    with pytest.raises(ValueError, match="depth: .*columns are not consecutive"):
        reproject.warp(planes[:, :H, :H], np.ascontiguousarray(depth[:H, :H]).T, **KW)
    with pytest.raises(ValueError, match="columns are not consecutive"):
        reproject.warp(planes[:, :, ::-1], depth, **KW)
    # Rows in reverse order: a negative row stride, which the library refuses with its own message.
    with pytest.raises(ValueError, match="stride"):
        reproject.warp(planes, depth[::-1], **KW)
    with pytest.raises(ValueError, match=r"expected \(H, W\), \(H, W, C\) or \(C, H, W\)"):
        reproject.warp(planes[:, :-1], depth, **KW)
    with pytest.raises(ValueError, match=r"does not fit"):
        reproject.warp(np.zeros((H, W, 5), np.float32), depth, **KW)


def test_wrong_dtypes_are_type_errors():
    color, depth = frame()
    with pytest.raises(TypeError, match="depth: expected a float32 array, got float64"):
        reproject.warp(color, depth.astype(np.float64), **KW)
    with pytest.raises(TypeError, match="color: expected a float32 array"):
        reproject.warp(color.astype(np.float64), depth, **KW)
    with pytest.raises(TypeError, match="float32"):
        reproject.warp(color, depth.astype(">f4"), **KW)


def test_parameters_are_checked_by_the_library():
    color, depth = frame()
    with pytest.raises(ValueError, match="near plane nan"):
        reproject.warp(color, depth, encoding="standard", near=float("nan"), far=20, convergence=3.5)
    with pytest.raises(ValueError, match="far"):
        reproject.warp(color, depth, encoding="standard", near=1, far=0.5, convergence=3.5)
    with pytest.raises(ValueError, match="invalid|convergence|finite"):
        reproject.warp(color, depth, encoding="standard", near=1, far=20, separation=float("inf"), convergence=3.5)
    with pytest.raises(ValueError, match="hole threshold|hole_threshold"):
        reproject.warp(color, depth, hole_threshold=float("nan"), **KW)
    with pytest.raises(ValueError, match="march"):
        reproject.warp(color, depth, march_steps=0, **KW)
    with pytest.raises(ValueError, match="unknown method 'fast'"):
        reproject.warp(color, depth, method="fast", **KW)
    with pytest.raises(ValueError, match="guard"):
        reproject.warp(color, depth, guard=W, **KW)


def test_out_reuses_the_arrays():
    color, depth = frame()
    first = reproject.warp(color, depth, **KW)
    arrays = [first.color, first.depth, first.status, first.source_x]
    addresses = [a.__array_interface__["data"][0] for a in arrays]
    for field in arrays:
        field[...] = 0
    again = reproject.warp(color, depth, out=first, **KW)
    assert [a.__array_interface__["data"][0] for a in (again.color, again.depth, again.status, again.source_x)] == addresses
    assert_same_result(again, reproject.warp(color, depth, **KW))
    # A colour array alone: only colour is written.
    planes = np.ascontiguousarray(np.moveaxis(color, -1, 0))
    out = np.empty_like(planes)
    only = reproject.warp(planes, depth, out=out, **KW)
    assert only.color is out and only.depth is None and only.status is None
    assert np.array_equal(out, np.moveaxis(first.color, -1, 0))


def test_bad_outputs_are_refused():
    color, depth = frame()
    planes = np.ascontiguousarray(np.moveaxis(color, -1, 0))
    with pytest.raises(ValueError, match="read-only"):
        out = np.empty_like(planes)
        out.flags.writeable = False
        reproject.warp(planes, depth, out=out, **KW)
    with pytest.raises(TypeError, match="out.color: expected a float32"):
        reproject.warp(planes, depth, out=np.empty(planes.shape), **KW)
    with pytest.raises(ValueError, match="not laid out like the source"):
        reproject.warp(planes, depth, out=np.empty((H, W, 3), np.float32), **KW)
    with pytest.raises(ValueError, match="packs its pixels"):
        reproject.warp(color, depth, out=np.empty((H, W, 3), np.float32), **KW)
    # The output over the input: the library's aliasing check.
    with pytest.raises(ValueError, match="overlap"):
        reproject.warp(planes, depth, out=planes, **KW)
    r = reproject.Result()
    r.color = np.empty_like(planes)
    r.depth = np.empty((H, W - 1), np.float32)
    with pytest.raises(ValueError, match=r"out.depth: expected shape \(64, 96\)"):
        reproject.warp(planes, depth, out=r, **KW)


def test_guard_band_narrows_the_target():
    color, depth = frame()
    r = reproject.warp(color, depth, guard=8, **KW)
    assert r.color.shape == (H, W - 16, 3) and r.depth.shape == (H, W - 16)


def test_rgba_is_read_and_written_in_place():
    color, depth = frame(channels=4)
    r = reproject.warp(color, depth, **KW)
    assert r.color.shape == (H, W, 4) and r.color.flags.c_contiguous
    out = reproject.Result()
    out.color = np.zeros((H, W, 4), np.float32)
    reproject.warp(color, depth, out=out, **KW)
    assert np.array_equal(out.color, r.color)
