# Engine-native pixel formats in Python: uint8 / float16 (H, W, 4) colour, uint16 / uint32 / packed
# uint8 depth, read and written in place. The relation to the float path is the one
# tests/test_pixel_formats.cpp (NativeMatchesTheFloatPath) asserts for the C++ API: the same frame
# as floats holding the values the formats decode to gives identical status and source x, float
# and rgba16f outputs identical, the byte and unorm formats within one code of the float result
# stored in the format. Every fused arch gives identical bytes; crops are read and written in
# place; what the module cannot take raises a clear error.
import numpy as np
import pytest

import reproject
import teddy

H, W = 24, 80
NEAR, FAR = 1.0, 40.0  # the standard encoding's planes (every depth format but packed)
PACKED_RANGE = (0.5, 40.0)  # rgba8_packed_linear's linear range
STEREO = dict(separation=0.08, convergence=3.5)
COLORS = ["rgba8", "rgba8_srgb", "rgba16f", "float32"]
DEPTHS = ["float32", "unorm16", "unorm24_s8", "s8_unorm24", "rgba8_packed_linear"]
PAIRS = [(c, d) for c in COLORS for d in DEPTHS]
ARCHES = [a for a in reproject.arches if reproject.arch_supported(a)]
# scalar, avx2 and avx512 fuse multiply-adds and store the same bits; sse does not fuse, and may
# differ from them in the last bits (docs/BEHAVIOUR.md "Instruction sets and FMA policy").
FUSED = [a for a in ARCHES if a != "sse"]
# Two option sets per case: the defaults, and fills, edges, a guard band and clipping that take
# the other resolve paths (every pixel written, as the C++ comparison requires).
VARIANTS = [dict(), dict(hole_fill="foreground", edge="mirror", guard=4, max_negative_parallax=2.0)]

STATS = {"cases": 0, "pixels": 0, "color_off": 0, "color_max": 0, "depth_off": dict.fromkeys(DEPTHS, 0),
         "depth_max": 0, "sse_same": 0, "sse_runs": 0}


@pytest.fixture(scope="module", autouse=True)
def summary():
    yield
    if STATS["cases"]:
        print(f"\nformats: {STATS['cases']} native-vs-float runs, {STATS['pixels']} pixels: status and source_x "
              f"identical; colour {STATS['color_off']} channels off (max {STATS['color_max']} LSB), depth "
              f"codes off {STATS['depth_off']} (max {STATS['depth_max']} code)")
    if STATS["sse_runs"]:
        print(f"formats: sse equal to scalar bit for bit in {STATS['sse_same']} of {STATS['sse_runs']} runs")


# ---- frames -------------------------------------------------------------------------------------

def scene_z(seed, height=H, width=W):
    """Linear depth per pixel, row by row: flat and sloped runs, near objects and far background,
    so that rows have walls (holes) both ways (as the C++ test's make_frames)."""
    rng = np.random.default_rng(seed)
    z = np.empty((height, width))
    for y in range(height):
        x = 0
        while x < width:
            flat = rng.random() < 0.3
            length = 1 + int(rng.random() * (40 if flat else 12))
            z0 = 30.0 if rng.random() < 0.2 else 1.5 + 20.0 * rng.random()
            slope = 0.0 if flat else (rng.random() - 0.5) * 0.5
            run = np.clip(z0 + slope * np.arange(min(length, width - x)), 1.2, 38.0)
            z[y, x:x + run.size] = run
            x += run.size
    return z


def stencil_of(height, width):
    """The bits that are not depth (D24S8's stencil, packed depth's A): a column pattern, so that
    the output shows which source column they came from."""
    return ((np.arange(width)[None, :] * 7 + np.arange(height)[:, None]) & 0xFF).astype(np.uint32)


def srgb_to_linear(byte):
    e = byte.astype(np.float64) / 255.0
    return np.where(e <= 0.04045, e / 12.92, ((e + 0.055) / 1.055) ** 2.4).astype(np.float32)


def linear_to_srgb(linear):
    """The byte nearest to `linear` on the sRGB curve (formats::linear_to_srgb, in double)."""
    l = np.clip(np.nan_to_num(linear.astype(np.float64), nan=0.0), 0.0, 1.0)
    e = np.where(l <= 0.0031308, l * 12.92, 1.055 * l ** (1.0 / 2.4) - 0.055)
    return np.floor(255.0 * e + 0.5).astype(np.int64)


def make_color(fmt, seed, height=H, width=W):
    """(native array, its keyword arguments, the float32 RGBA the format decodes to)."""
    rng = np.random.default_rng(seed + 1000)
    if fmt in ("rgba8", "rgba8_srgb"):
        native = rng.integers(0, 256, (height, width, 4), dtype=np.uint8)
        floats = native.astype(np.float32)  # rgba8 is blended as the byte values
        if fmt == "rgba8_srgb":
            floats[..., :3] = srgb_to_linear(native[..., :3])  # alpha stays linear
            return native, dict(color_space="srgb"), floats
        return native, {}, floats
    if fmt == "rgba16f":
        native = ((rng.random((height, width, 4)) - 0.2) * 3.0).astype(np.float16)
        return native, {}, native.astype(np.float32)  # every half is a float
    native = rng.random((height, width, 4), dtype=np.float32)
    return native, {}, native


def make_depth(fmt, seed, height=H, width=W):
    """(native array, its keyword arguments incl. the decoder, the float32 depth it decodes to)."""
    z = scene_z(seed, height, width)
    stencil = stencil_of(height, width)
    if fmt == "rgba8_packed_linear":
        near, far = PACKED_RANGE
        code = np.clip(np.rint((z - near) / (far - near) * 16581375.0), 0, 16581374).astype(np.int64)
        native = np.stack([code // 65025, code // 255 % 255, code % 255, stencil], axis=-1).astype(np.uint8)
        # v = code / 16581375 correctly rounded (both exact in float), then d = v (far - near) + near:
        # two float roundings, never fused (docs/BEHAVIOUR.md "Pixel formats").
        v = code.astype(np.float32) / np.float32(16581375.0)
        floats = v * (np.float32(far) - np.float32(near)) + np.float32(near)
        return native, dict(depth_format=fmt, linear_range=PACKED_RANGE), floats.astype(np.float32)
    d = (1.0 / NEAR - 1.0 / z) / (1.0 / NEAR - 1.0 / FAR)  # the standard encoding
    decoder = dict(encoding="standard", near=NEAR, far=FAR)
    if fmt == "float32":
        native = d.astype(np.float32)
        return native, decoder, native
    if fmt == "unorm16":
        native = np.rint(d * 65535.0).astype(np.uint16)
        return native, decoder, (native / 65535.0).astype(np.float32)  # correctly rounded, as the library's
    code = np.rint(d * 16777215.0).astype(np.uint32)
    native = code | stencil << 24 if fmt == "unorm24_s8" else code << 8 | stencil
    return native, dict(decoder, depth_format=fmt), (code / 16777215.0).astype(np.float32)


# ---- the float path's outputs in the formats ------------------------------------------------------

def color_lsb(fmt, native, floats):
    """Per channel: how many codes the native output is from the float output stored in `fmt`."""
    if fmt == "rgba16f":  # the same blend, rounded once to half (numpy rounds to nearest even)
        return (native.view(np.uint16) != floats.astype(np.float16).view(np.uint16)).astype(np.int64) * 2
    if fmt == "float32":
        return (native.view(np.uint32) != floats.view(np.uint32)).astype(np.int64) * 2
    expected = np.clip(np.rint(np.nan_to_num(floats.astype(np.float64))), 0, 255).astype(np.int64)
    if fmt == "rgba8_srgb":
        expected[..., :3] = linear_to_srgb(floats[..., :3])
    return np.abs(native.astype(np.int64) - expected)


def depth_code(fmt, depth):
    """The depth code a native output holds, and the bits that are not depth (None: none)."""
    if fmt == "unorm16":
        return depth.astype(np.int64), None
    if fmt == "unorm24_s8":
        return (depth & 0xFFFFFF).astype(np.int64), depth >> 24
    if fmt == "s8_unorm24":
        return (depth >> 8).astype(np.int64), depth & 0xFF
    if fmt == "rgba8_packed_linear":
        d = depth.astype(np.int64)
        return d[..., 0] * 65025 + d[..., 1] * 255 + d[..., 2], depth[..., 3]
    return depth.view(np.uint32).astype(np.int64), None


def expected_code(fmt, floats):
    """The float output depth stored in `fmt` (round to nearest even, clamped)."""
    f = floats.astype(np.float64)
    if fmt == "unorm16":
        return np.clip(np.rint(f * 65535.0), 0, 65535).astype(np.int64)
    if fmt in ("unorm24_s8", "s8_unorm24"):
        return np.clip(np.rint(f * 16777215.0), 0, 16777215).astype(np.int64)
    if fmt == "rgba8_packed_linear":
        near, far = PACKED_RANGE
        return np.clip(np.rint((f - near) / (far - near) * 16581375.0), 0, 16581374).astype(np.int64)
    return floats.view(np.uint32).astype(np.int64)


def check_kept_bits(fmt, native, result, guard):
    """The stencil byte / packed A of every output pixel is the source pixel's of column j0 (the
    column it interpolates from: floor(x*); for a hole, the fill column, one of j0, j0 + 1)."""
    _, kept = depth_code(fmt, result.depth)
    if kept is None:
        return
    _, source_bits = depth_code(fmt, native)
    x, status = result.source_x, result.status
    rows = np.broadcast_to(np.arange(x.shape[0])[:, None], x.shape)
    last = native.shape[1] - 1
    j0 = np.floor(np.clip(np.nan_to_num(x), 0, last)).astype(np.int64)
    j1 = np.minimum(j0 + 1, last)
    hit, hole = status == 0, status == 1
    assert np.array_equal(kept[hit], source_bits[rows, j0][hit])
    assert np.all((kept[hole] == source_bits[rows, j0][hole]) | (kept[hole] == source_bits[rows, j1][hole]))


def assert_native_matches_float(color_fmt, depth_fmt, native, floats, depth_native, guard):
    assert np.array_equal(native.status, floats.status), "status"
    assert np.array_equal(native.source_x.view(np.uint32), floats.source_x.view(np.uint32)), "source_x"
    lsb = color_lsb(color_fmt, native.color, floats.color)
    assert lsb.max() <= 1, f"colour {lsb.max()} codes off"
    code, _ = depth_code(depth_fmt, native.depth)
    depth_lsb = np.abs(code - expected_code(depth_fmt, floats.depth))
    assert depth_lsb.max() <= 1, f"depth {depth_lsb.max()} codes off"
    check_kept_bits(depth_fmt, depth_native, native, guard)
    STATS["cases"] += 1
    STATS["pixels"] += native.status.size
    STATS["color_off"] += int(np.count_nonzero(lsb))
    STATS["color_max"] = max(STATS["color_max"], int(lsb.max()))
    STATS["depth_off"][depth_fmt] += int(np.count_nonzero(depth_lsb))
    STATS["depth_max"] = max(STATS["depth_max"], int(depth_lsb.max()))


def frame(color_fmt, depth_fmt, seed):
    color, color_kw, color_f = make_color(color_fmt, seed)
    depth, depth_kw, depth_f = make_depth(depth_fmt, seed)
    float_kw = {k: v for k, v in depth_kw.items() if k not in ("depth_format", "linear_range")}
    return (color, depth, dict(color_kw, **depth_kw, **STEREO)), (color_f, depth_f, dict(float_kw, **STEREO))


# ---- native == the float path ---------------------------------------------------------------------

@pytest.mark.parametrize("method", reproject.methods)
@pytest.mark.parametrize("color_fmt,depth_fmt", PAIRS)
def test_native_matches_the_float_path(color_fmt, depth_fmt, method):
    (color, depth, kw), (color_f, depth_f, float_kw) = frame(color_fmt, depth_fmt, seed=len(method))
    for arch in ARCHES:
        for variant in VARIANTS:
            options = dict(variant, method=method, arch=arch)
            native = reproject.warp(color, depth, **kw, **options)
            assert native.color.dtype == color.dtype and native.color.shape == (H, W - 2 * options.get("guard", 0), 4)
            assert native.depth.dtype == depth.dtype and native.depth.shape[2:] == depth.shape[2:]
            floats = reproject.warp(color_f, depth_f, **float_kw, **options)
            assert_native_matches_float(color_fmt, depth_fmt, native, floats, depth, options.get("guard", 0))
            # Both eyes in one call: each eye as its own warp, against the float path's pair.
            pair = reproject.warp_pair(color, depth, **kw, **options)
            pair_f = reproject.warp_pair(color_f, depth_f, **float_kw, **options)
            for eye, eye_f in zip(pair, pair_f):
                assert_native_matches_float(color_fmt, depth_fmt, eye, eye_f, depth, options.get("guard", 0))


def result_bytes(r):
    return [np.ascontiguousarray(getattr(r, f)).view(np.uint8).tobytes() for f in ("color", "depth", "status", "source_x")]


@pytest.mark.parametrize("method", reproject.methods)
@pytest.mark.parametrize("color_fmt,depth_fmt", PAIRS)
def test_every_fused_arch_gives_the_same_bytes(color_fmt, depth_fmt, method):
    (color, depth, kw), _ = frame(color_fmt, depth_fmt, seed=7)
    for variant in VARIANTS:
        outputs = {a: result_bytes(reproject.warp(color, depth, method=method, arch=a, **variant, **kw)) for a in ARCHES}
        for arch in FUSED[1:]:
            assert outputs[arch] == outputs[FUSED[0]], f"{arch} differs from {FUSED[0]}"
        if "sse" in outputs:  # checked against the float path above; here only counted
            STATS["sse_runs"] += 1
            STATS["sse_same"] += outputs["sse"] == outputs["scalar"]


# ---- in place: crops, odd strides, strided outputs ----------------------------------------------------

def embed(a, rows_before=3, rows_after=2, columns_before=5, columns_after=9, fill=0x5A):
    """`a` as a crop of a larger array (its parent), and the parent."""
    shape = (a.shape[0] + rows_before + rows_after, a.shape[1] + columns_before + columns_after) + a.shape[2:]
    parent = np.empty(shape, a.dtype)
    parent.view(np.uint8).fill(fill)
    crop = parent[rows_before:rows_before + a.shape[0], columns_before:columns_before + a.shape[1]]
    crop[...] = a
    return crop, parent


def odd_strides(a):
    """`a` (C-contiguous) in a byte buffer with an odd row stride and an odd start: rows of whole
    pixels no dtype's alignment holds (numpy calls such arrays unaligned)."""
    row = a.shape[1] * a.strides[1] + 3
    buffer = np.zeros(1 + row * (a.shape[0] - 1) + a.shape[1] * a.strides[1], np.uint8)  # ends with the last row
    view = np.ndarray(a.shape, a.dtype, buffer, offset=1, strides=(row,) + a.strides[1:])
    view[...] = a
    return view


@pytest.mark.parametrize("method", ["scanline", "exact"])
@pytest.mark.parametrize("color_fmt,depth_fmt", [p for p in PAIRS if p != ("float32", "float32")])
def test_crops_are_read_and_written_in_place(color_fmt, depth_fmt, method):
    (color, depth, kw), _ = frame(color_fmt, depth_fmt, seed=3)
    reference = reproject.warp(color, depth, method=method, **kw)
    crop_color, _ = embed(color)
    crop_depth, _ = embed(depth, 2, 4, 11, 1)
    assert not crop_color.flags.c_contiguous and not crop_depth.flags.c_contiguous
    assert result_bytes(reproject.warp(crop_color, crop_depth, method=method, **kw)) == result_bytes(reference)
    # Crops whose last row ends where their parent's memory ends: a read past a row would leave it
    # (the sanitizer build runs this file too).
    at_end = reproject.warp(embed(color, 3, 0, 5, 0)[0], embed(depth, 1, 0, 7, 0)[0], method=method, **kw)
    assert result_bytes(at_end) == result_bytes(reference)
    if color.dtype != np.float32 and depth.dtype != np.float32:  # engine rows need no alignment
        unaligned = reproject.warp(odd_strides(color), odd_strides(depth), method=method, **kw)
        assert result_bytes(unaligned) == result_bytes(reference)
    # Outputs as crops of larger arrays: written in place, nothing around them touched.
    out, parents = reproject.Result(), {}
    for field in ("color", "depth", "status", "source_x"):
        value = getattr(reference, field)
        crop, parent = embed(np.zeros_like(value), 1, 2, 3, 4, fill=0xC3)
        setattr(out, field, crop)
        parents[field] = (parent, parent.copy(), crop)
    again = reproject.warp(color, depth, method=method, out=out, **kw)
    assert again.color is out.color and again.depth is out.depth
    assert result_bytes(again) == result_bytes(reference)
    for field, (parent, before, crop) in parents.items():
        outside = np.ones(parent.shape[:2], bool)
        outside[1:1 + crop.shape[0], 3:3 + crop.shape[1]] = False
        assert np.array_equal(parent[outside].view(np.uint8), before[outside].view(np.uint8)), field


def test_pair_writes_native_outputs_in_place():
    (color, depth, kw), _ = frame("rgba8", "unorm24_s8", seed=5)
    left, right = reproject.warp_pair(color, depth, method="secant", **kw)
    out_left, out_right = reproject.Result(), reproject.Result()
    out_left.color, out_left.depth = np.zeros_like(left.color), np.zeros_like(left.depth)
    out_right.color = embed(np.zeros_like(right.color))[0]
    again = reproject.warp_pair(color, depth, method="secant", out_left=out_left, out_right=out_right, **kw)
    assert np.array_equal(again.left.color, left.color) and np.array_equal(again.left.depth, left.depth)
    assert np.array_equal(out_right.color, right.color) and again.right.depth is None


# ---- errors ------------------------------------------------------------------------------------------

def test_layouts_the_library_cannot_take_are_refused():
    (color, depth, kw), _ = frame("rgba8", "unorm16", seed=1)
    with pytest.raises(ValueError, match=r"depth: uint16 array .*columns are not consecutive pixels.*"
                                         r"numpy.ascontiguousarray\(depth\)"):
        reproject.warp(color[:, ::2], depth[:, ::2], **kw)
    with pytest.raises(ValueError, match=r"color: uint8 array .*columns are not consecutive pixels"):
        reproject.warp(color[:, ::2], np.ascontiguousarray(depth[:, ::2]), **kw)
    with pytest.raises(ValueError, match=r"color: .*channels of its pixels are not consecutive"):
        reproject.warp(color[..., ::-1], depth, **kw)  # BGRA seen as RGBA: a view numpy makes, the library cannot read
    planes = np.ascontiguousarray(np.moveaxis(color, -1, 0))
    with pytest.raises(ValueError, match=r"color: .*not consecutive"):
        reproject.warp(np.moveaxis(planes, 0, -1), depth, **kw)
    with pytest.raises(ValueError, match=r"depth: .*columns are not consecutive"):
        reproject.warp(color[:, :H], np.ascontiguousarray(depth[:H, :H]).T, **kw)
    packed, packed_kw, _ = make_depth("rgba8_packed_linear", 1)
    with pytest.raises(ValueError, match=r"depth: .*channels of its pixels are not consecutive"):
        reproject.warp(color, packed[..., ::-1], **packed_kw, **STEREO)
    # Rows in reverse order: a negative row stride, which the library refuses with its own message.
    with pytest.raises(ValueError, match="stride"):
        reproject.warp(color, depth[::-1], **kw)
    with pytest.raises(ValueError, match="stride"):
        reproject.warp(color[::-1], depth, **kw)


def test_empty_frames_and_misaligned_float_rgba():
    (color, depth, kw), _ = frame("rgba8", "unorm16", seed=1)
    # An empty frame is no error for the library; numpy gives its arrays strides (0, 0), which must
    # not be mistaken for a layout the library cannot read.
    # (A model from separation and convergence needs the image width: an explicit one here.)
    model = reproject.ParallaxModel(2.0, -8.0)
    decoder = {k: kw[k] for k in ("encoding", "near", "far") if k in kw}
    for rows, cols in ((0, W), (H, 0), (0, 0)):
        result = reproject.warp(np.zeros((rows, cols, 4), np.uint8), np.zeros((rows, cols), np.uint16), model=model,
                                **decoder)
        assert result.color.shape == (rows, cols, 4) and result.color.dtype == np.uint8
        result = reproject.warp(np.zeros((rows, cols, 4), np.float32), np.zeros((rows, cols), np.float32),
                                encoding="linear", model=model)
        assert result.color.shape == (rows, cols, 4)
    # Float RGBA one byte off a float boundary: refused like every other float view (it would be
    # read through misaligned float pointers).
    raw = np.zeros(H * W * 16 + 4, np.uint8)
    shifted = np.ndarray((H, W, 4), np.float32, buffer=raw, offset=1)
    with pytest.raises(ValueError, match=r"color: .*not aligned to whole floats"):
        reproject.warp(shifted, depth.astype(np.float32) / 65535, encoding="linear", **STEREO)


def test_wrong_dtypes_are_type_errors_listing_the_accepted():
    (color, depth, kw), _ = frame("rgba8", "unorm16", seed=1)
    for bad in (color.astype(np.uint16), color.astype(np.float64), color.astype(np.int8)):
        with pytest.raises(TypeError, match=r"color: expected a float32 array, got .*float32, and uint8 or float16 as "
                                            r"\(H, W, 4\) RGBA"):
            reproject.warp(bad, depth, **kw)
    for bad in (depth.astype(np.int16), depth.astype(np.float64), depth.astype(">u2"), depth.astype(np.uint64)):
        with pytest.raises(TypeError, match=r"depth: expected a float32 array, got .*uint16 \(D16 codes\) and uint32 "
                                            r"\(D24S8 words\) as \(H, W\), and uint8 as \(H, W, 4\)") as error:
            reproject.warp(color, bad, **kw)
        # No cast is suggested: float32 depth is the stored value, so D16 codes cast to float would
        # be read as depths. Only the byte order has a lossless fix.
        assert "astype(numpy.float32)" not in str(error.value)
        assert ("byte order is not the machine's" in str(error.value)) == (bad.dtype == np.dtype(">u2")), error.value
    with pytest.raises(TypeError, match=r"depth_format='unorm16' reads a uint16 array in the machine's byte order, "
                                        r"got .*>u2.*newbyteorder\('='\)"):
        reproject.warp(color, depth.astype(">u2"), depth_format="unorm16", **kw)
    with pytest.raises(TypeError, match=r"color: .*byte order is not the machine's"):
        reproject.warp(color.astype(np.float32).astype(">f4"), depth, **kw)
    with pytest.raises(TypeError, match=r"depth: depth_format='unorm16' reads a uint16 array .*, got float32"):
        reproject.warp(color, depth.astype(np.float32), depth_format="unorm16", **kw)
    with pytest.raises(TypeError, match=r"depth_format='unorm24_s8' reads a uint32 array .*, got uint16"):
        reproject.warp(color, depth, depth_format="unorm24_s8", **kw)
    with pytest.raises(TypeError, match=r"out.color: expected a uint8 array \(the source's dtype\), got float32"):
        reproject.warp(color, depth, out=np.zeros((H, W, 4), np.float32), **kw)
    out = reproject.Result()
    out.color, out.depth = np.zeros_like(color), np.zeros((H, W), np.float32)
    with pytest.raises(TypeError, match=r"out.depth: expected a uint16 array \(the source's dtype\), got float32"):
        reproject.warp(color, depth, out=out, **kw)


def test_what_the_dtype_does_not_say_is_asked_for():
    (color, d24, kw), _ = frame("rgba8", "unorm24_s8", seed=1)
    del kw["depth_format"]
    with pytest.raises(ValueError, match=r"uint32 .*D24S8.*depth_format='unorm24_s8'.*depth_format='s8_unorm24'"):
        reproject.warp(color, d24, **kw)
    packed, packed_kw, _ = make_depth("rgba8_packed_linear", 1)
    with pytest.raises(ValueError, match=r"depth_format='rgba8_packed_linear' and linear_range"):
        reproject.warp(color, packed, **STEREO)
    with pytest.raises(ValueError, match=r"needs linear_range=\(near, far\)"):
        reproject.warp(color, packed, depth_format="rgba8_packed_linear", **STEREO)
    with pytest.raises(ValueError, match=r"linear_range= is for depth_format='rgba8_packed_linear' only"):
        reproject.warp(color, d24, depth_format="s8_unorm24", linear_range=(1, 2), **kw)
    with pytest.raises(ValueError, match=r"unknown depth_format 'd24'"):
        reproject.warp(color, d24, depth_format="d24", **kw)
    with pytest.raises(ValueError, match=r"unknown color_space 'rgb'"):
        reproject.warp(color, d24, color_space="rgb", depth_format="s8_unorm24", **kw)
    with pytest.raises(ValueError, match=r"color_space='srgb' is for uint8 colour"):
        reproject.warp(color.astype(np.float16), d24, color_space="srgb", depth_format="s8_unorm24", **kw)


def test_shapes_and_library_refusals_are_value_errors():
    (color, depth, kw), _ = frame("rgba8", "unorm16", seed=1)
    with pytest.raises(ValueError, match=r"color: uint8 colour is RGBA: expected shape \(24, 80, 4\).*convert\('RGBA'\)"):
        reproject.warp(color[..., :3], depth, **kw)  # Pillow's RGB
    with pytest.raises(ValueError, match=r"color: float16 colour is RGBA"):
        reproject.warp(color.astype(np.float16)[:-1], depth, **kw)
    with pytest.raises(ValueError, match=r"depth: expected an \(H, W\) array"):
        reproject.warp(color, depth[..., None], **kw)
    packed, packed_kw, _ = make_depth("rgba8_packed_linear", 1)
    with pytest.raises(ValueError, match=r"rgba8_packed_linear depth is an \(H, W, 4\) array"):
        reproject.warp(color, packed[..., :3], **packed_kw, **STEREO)
    # The library's own checks, with its messages.
    for bad in ((1.0, 1.0), (0.0, float("inf")), (float("nan"), 1.0)):
        with pytest.raises(ValueError, match=r"source depth_buffer: rgba8_packed_linear range .* must be finite"):
            reproject.warp(color, packed, depth_format="rgba8_packed_linear", linear_range=bad, **STEREO)
    with pytest.raises(ValueError, match="overlap"):
        reproject.warp(color, depth, out=color, **kw)
    out = reproject.Result()
    out.color = np.zeros((H, W - 1, 4), np.uint8)
    with pytest.raises(ValueError, match=r"out.color: expected shape \(24, 80, 4\)"):
        reproject.warp(color, depth, out=out, **kw)
    out.color = np.zeros_like(color)
    out.color.flags.writeable = False
    with pytest.raises(ValueError, match="out.color: the array is read-only"):
        reproject.warp(color, depth, out=out, **kw)


# ---- real data --------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def teddy_pair(data_dir):
    left, right, disp_left, disp_right = teddy.load(data_dir)
    rgba = np.dstack([left, np.full(left.shape[:2], 255, np.uint8)])
    return rgba, right, teddy.fill_unknown(disp_left), teddy.visible_in_both(disp_left, disp_right)


@pytest.mark.parametrize("method", reproject.methods)
def test_teddy_as_uint8_rgba_scores_as_the_float_path(teddy_pair, method):
    rgba, right, disparity, mask = teddy_pair
    kw = dict(encoding="disparity", direction="left-to-right", method=method)
    floats = reproject.warp(rgba.astype(np.float32), disparity, **kw)
    native = reproject.warp(rgba, disparity, **kw)
    srgb = reproject.warp(rgba, disparity, color_space="srgb", **kw)
    assert native.color.dtype == np.uint8 and np.array_equal(native.status, floats.status)
    assert np.abs(native.color.astype(np.int64) - np.rint(floats.color)).max() <= 1  # the float path's bytes
    psnr_float, _, _ = teddy.score(floats.color, right, mask)
    psnr_native, _, _ = teddy.score(native.color, right, mask)
    psnr_srgb, _, _ = teddy.score(srgb.color, right, mask)
    print(f"[ teddy    ] {method:<9} float {psnr_float:.3f} dB, uint8 rgba8 {psnr_native:.3f} dB, "
          f"rgba8_srgb {psnr_srgb:.3f} dB")
    assert abs(psnr_native - psnr_float) <= 0.05
