# The Python module at its boundaries (issue 21): side-by-side buffers are accepted while a real
# overlap is still refused (defect 3); sizes are checked in 64 bits before anything is allocated
# (defect 4); and every error names the argument, shows its value briefly, and says the rule and
# the fix in at most two lines (defect 5).
import numpy as np
import pytest

import reproject

H, W = 24, 80
KW = dict(encoding="standard", near=1.0, far=20.0, separation=0.03, convergence=3.5)


def scene(height=H, width=W, seed=2):
    rng = np.random.default_rng(seed)
    color = rng.random((height, width, 4), dtype=np.float32)
    z = 2.0 + 6.0 * rng.random((height, 1)) + np.linspace(0, 3, width)[None, :]
    z[height // 4: height // 2, width // 3: width // 2] = 2.2
    depth = ((1.0 - 1.0 / z) / (1.0 - 1.0 / 20.0)).astype(np.float32)
    return color, depth


def short(message):
    """A message of at most two lines, none of them a dump of the argument."""
    assert message.count("\n") <= 1, message
    assert len(message) <= 400, f"{len(message)} characters: {message[:500]}"
    return message


def error_of(kind, call):
    with pytest.raises(kind) as info:
        call()
    return short(str(info.value))


# ---- Defect 3: side-by-side buffers --------------------------------------------------------------

def test_left_half_in_right_half_out_of_one_array():
    color, depth = scene()
    expected = reproject.warp(color, depth, **KW)
    sbs = np.zeros((H, 2 * W, 4), np.float32)
    sbs[:, :W] = color
    depths = np.zeros((H, 2 * W), np.float32)
    depths[:, :W] = depth
    out = reproject.Result()
    out.color, out.depth = sbs[:, W:], depths[:, W:]
    reproject.warp(sbs[:, :W], depths[:, :W], out=out, **KW)
    assert np.array_equal(sbs[:, W:], expected.color)
    assert np.array_equal(depths[:, W:], expected.depth)
    assert np.array_equal(sbs[:, :W], color) and np.array_equal(depths[:, :W], depth)  # inputs untouched


def test_engine_buffers_side_by_side():
    rng = np.random.default_rng(5)
    pixels = np.zeros((H, 2 * W, 4), np.uint8)
    pixels[:, :W] = rng.integers(0, 256, (H, W, 4), dtype=np.uint8)
    d16 = np.zeros((H, 2 * W), np.uint16)
    d16[:, :W] = rng.integers(30000, 60000, (H, W), dtype=np.uint16)
    expected = reproject.warp(pixels[:, :W].copy(), d16[:, :W].copy(), **KW)
    out = reproject.Result()
    out.color, out.depth = pixels[:, W:], d16[:, W:]
    reproject.warp(pixels[:, :W], d16[:, :W], out=out, **KW)
    assert np.array_equal(pixels[:, W:], expected.color) and np.array_equal(d16[:, W:], expected.depth)


def test_pair_into_one_side_by_side_picture():
    color, depth = scene()
    left, right = reproject.warp_pair(color, depth, **{k: v for k, v in KW.items()})
    picture = np.zeros((H, 2 * W, 4), np.float32)
    out_left, out_right = reproject.Result(), reproject.Result()
    out_left.color, out_right.color = picture[:, :W], picture[:, W:]
    reproject.warp_pair(color, depth, out_left=out_left, out_right=out_right, **KW)
    assert np.array_equal(picture[:, :W], left.color) and np.array_equal(picture[:, W:], right.color)


def test_a_real_overlap_is_still_refused():
    color, depth = scene()
    sbs = np.zeros((H, 2 * W, 4), np.float32)
    sbs[:, :W] = color
    before = sbs.copy()
    out = reproject.Result()
    out.color = sbs[:, W - 1: 2 * W - 1]  # one pixel of every row is also read
    message = error_of(ValueError, lambda: reproject.warp(sbs[:, :W], depth, out=out, **KW))
    assert "overlap" in message
    assert np.array_equal(sbs, before)


# ---- Defect 4: sizes checked in 64 bits before allocating --------------------------------------

@pytest.mark.parametrize("guard", [2**30 + 40, 2**30, 2**31 - 1, W // 2, -1])
def test_a_guard_band_beyond_the_source_is_a_value_error_naming_it(guard):
    color, depth = scene()
    message = error_of(ValueError, lambda: reproject.warp(color, depth, guard=guard, **KW))
    assert "guard" in message and str(guard) in message


@pytest.mark.parametrize("guard", [2**31, -2**31 - 1, 2**64])
def test_a_guard_beyond_int_is_named(guard):
    color, depth = scene()
    message = error_of((TypeError, ValueError), lambda: reproject.warp(color, depth, guard=guard, **KW))
    assert "guard" in message and str(guard) in message


# ---- Defect 5: messages that name the argument, the value, the rule and the fix ----------------

def test_a_plain_list_is_named_not_printed():
    color, depth = scene(64, 200)
    for name, call in (("color", lambda: reproject.warp(color.tolist(), depth, **KW)),
                       ("depth", lambda: reproject.warp(color, depth.tolist(), **KW)),
                       ("depth", lambda: reproject.warp_pair(color, depth.tolist(), **KW))):
        message = error_of(TypeError, call)
        assert f"{name}:" in message and "list" in message and "numpy" in message, message


def test_a_wrong_type_of_keyword_is_named():
    color, depth = scene()
    cases = {"convergence": "3.5", "threads": "2", "guard": 1.5, "method": 3, "hole_threshold": "big",
             "near": [1], "linear_range": 5, "decoder": "standard", "march_steps": None}
    for name, value in cases.items():
        kw = dict(KW)
        kw[name] = value
        message = error_of(TypeError, lambda: reproject.warp(color, depth, **kw))
        assert message.startswith("warp(): " + name + ":"), message
        assert repr(value)[:20] in message or type(value).__name__ in message, message


def test_an_unknown_keyword_is_named_with_the_closest_one():
    color, depth = scene()
    message = error_of(TypeError, lambda: reproject.warp(color, depth, convergnce=3.5, separation=0.03))
    assert "convergnce" in message and "convergence" in message


def test_other_functions_name_their_arguments_too():
    decoder = reproject.Decoder("standard", near=1.0, far=20.0)
    camera = reproject.StereoCamera(0.03, 3.5)
    _, depth = scene()
    assert "near" in error_of(TypeError, lambda: reproject.Decoder("standard", near="x", far=2.0))
    assert "depth" in error_of(TypeError, lambda: reproject.parallax_budget(depth.tolist(), decoder, camera))
    assert "camera" in error_of(TypeError, lambda: reproject.parallax_budget(depth, decoder, 3.5))
    assert "width" in error_of(TypeError, lambda: reproject.ParallaxModel.from_stereo(0.03, 3.5, "wide", "left-to-right"))
    assert "horizontal_fov" in error_of(TypeError, lambda: camera.eye_translation("60"))
    assert "radius" in error_of(TypeError, lambda: reproject.dilate_nearer_depth(depth, decoder, radius="2"))


def test_a_negative_row_stride_says_to_copy():
    color, depth = scene()
    for name, call in (("depth", lambda: reproject.warp(color, depth[::-1], **KW)),
                       ("color", lambda: reproject.warp(color[::-1], depth, **KW))):
        message = error_of(ValueError, call)
        assert message.startswith(name + ":") and f"numpy.ascontiguousarray({name})" in message, message


def test_a_zero_width_frame_is_an_empty_result():
    color, depth = scene()
    for rows, cols in ((H, 0), (0, W), (0, 0)):
        r = reproject.warp(color[:rows, :cols], depth[:rows, :cols], **KW)
        assert r.color.shape == (rows, cols, 4) and r.depth.shape == (rows, cols)
        left, right = reproject.warp_pair(color[:rows, :cols], depth[:rows, :cols], **KW)
        assert left.color.shape == right.color.shape == (rows, cols, 4)
    # The model's own parameters are still checked.
    message = error_of(ValueError, lambda: reproject.warp(color[:, :0], depth[:, :0], **dict(KW, convergence=-1.0)))
    assert "convergence" in message


def test_out_from_another_call_says_what_fits():
    color, depth = scene()
    for out in (reproject.Result(), reproject.warp(color[..., :3].copy(), depth, **KW),
                reproject.warp((color * 255).astype(np.uint8), depth, **KW)):
        message = error_of((TypeError, ValueError), lambda: reproject.warp(color, depth, out=out, **KW))
        assert message.startswith("out.color:"), message
        assert ".astype" not in message and "out=None" in message, message
    empty = reproject.Result()
    assert "None" in error_of((TypeError, ValueError), lambda: reproject.warp(color, depth, out=empty, **KW))


@pytest.mark.parametrize("name,value", [("hole_threshold", 1e39), ("max_negative_parallax", 5e38),
                                        ("probe_parallax", -1e39), ("linear_range", (0.0, 1e39))])
def test_a_float_beyond_float_range_is_not_reported_as_inf(name, value):
    color, depth = scene()
    kw = dict(KW)
    if name == "linear_range":
        packed = np.zeros((H, W, 4), np.uint8)
        call = lambda: reproject.warp(color, packed, depth_format="rgba8_packed_linear", linear_range=value,
                                      encoding="linear", separation=0.03, convergence=3.5)
    else:
        kw[name] = value
        call = lambda: reproject.warp(color, depth, **kw)
    message = error_of(ValueError, call)
    assert message.startswith(name + ":") and "inf" not in message and "float" in message, message


def test_parallax_model_floats_beyond_range():
    message = error_of(ValueError, lambda: reproject.ParallaxModel(1e39, 1.0))
    assert "a:" in message and "inf" not in message
