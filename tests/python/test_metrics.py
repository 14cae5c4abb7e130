# reproject.metrics: SSIM against scikit-image's structural_similarity (gaussian_weights=True,
# sigma=1.5, use_sample_covariance=False, the same data_range) on the teddy pair and on noise, float32
# and uint8, with and without a mask; PSNR against NumPy's formula; views, errors and the GIL.
#
# scikit-image is a test-only dependency (Debian: python3-skimage): without it the comparisons
# with it are skipped, saying so, and the rest runs.
import threading

import numpy as np
import pytest

import reproject
import reproject.metrics as metrics
import teddy

RADIUS = 5  # the map is averaged over the pixels at least this far from the border
SKIMAGE_TOLERANCE = 1e-4


@pytest.fixture(scope="module")
def structural_similarity():
    try:
        from skimage.metrics import structural_similarity
    except ImportError:
        pytest.skip("scikit-image is not installed (Debian: apt-get install python3-skimage): "
                    "SSIM is not compared with scikit-image's structural_similarity")
    return structural_similarity


def skimage_ssim(structural_similarity, a, b, data_range, mask=None):
    """scikit-image's mean SSIM of a and b; with a mask, its full map averaged over the mask's
    pixels inside the crop (and over the channels)."""
    color = a.ndim == 3
    mean, full = structural_similarity(a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
                                       data_range=data_range, channel_axis=2 if color else None, full=True)
    if mask is None:
        return float(mean)
    inner = (slice(RADIUS, -RADIUS), slice(RADIUS, -RADIUS))
    return float(full[inner][mask[inner]].mean())


def compare(structural_similarity, a, b, data_range, mask=None, name=""):
    """ours vs scikit-image on the arrays as given (float32 is computed in float32 there) and on
    float64 copies (scikit-image's exact figure, which ours should match to rounding)."""
    ours = metrics.ssim(a, b, mask=mask, data_range=data_range)
    given = skimage_ssim(structural_similarity, a, b, data_range if data_range is not None else default_range(a), mask)
    exact = skimage_ssim(structural_similarity, a.astype(np.float64), b.astype(np.float64),
                         data_range if data_range is not None else default_range(a), mask)
    print(f"[ ssim ] {name:<34} ours {ours:.10f}  skimage {given:.10f} (|d| {abs(ours - given):.2e}),"
          f" float64 {exact:.10f} (|d| {abs(ours - exact):.2e})")
    assert abs(ours - given) <= SKIMAGE_TOLERANCE
    assert abs(ours - exact) <= 1e-9
    return ours


def default_range(a):
    return 255.0 if a.dtype == np.uint8 else 1.0


@pytest.fixture(scope="module")
def teddy_views(data_dir):
    """The right view (truth), the left view reprojected to it by `exact`, and the pixels visible
    in both, as tests/python/test_teddy.py makes them."""
    left, right, disp_left, disp_right = teddy.load(data_dir)
    warped = reproject.warp(left.astype(np.float32), teddy.fill_unknown(disp_left), encoding="disparity",
                            direction="left-to-right", method="exact").color
    return right, left, warped, teddy.visible_in_both(disp_left, disp_right)


@pytest.fixture(scope="module")
def noise():
    rng = np.random.default_rng(22)
    a = rng.random((97, 131, 3), dtype=np.float32)
    b = np.clip(a + rng.normal(0.0, 0.15, a.shape), 0.0, 1.0).astype(np.float32)
    mask = rng.random((97, 131)) < 0.3
    return a, b, mask


# ---- SSIM against scikit-image -----------------------------------------------------------------

def test_teddy_uint8(structural_similarity, teddy_views):
    right, left, warped, mask = teddy_views
    warped8 = np.clip(np.rint(warped), 0, 255).astype(np.uint8)
    compare(structural_similarity, warped8, right, None, name="teddy exact vs right, uint8")
    compare(structural_similarity, warped8, right, None, mask, name="teddy exact vs right, uint8, mask")
    compare(structural_similarity, left, right, None, name="teddy left vs right, uint8")


def test_teddy_float32(structural_similarity, teddy_views):
    right, left, warped, mask = teddy_views
    truth = right.astype(np.float32)
    compare(structural_similarity, warped, truth, 255.0, name="teddy exact vs right, 0..255")
    compare(structural_similarity, warped / np.float32(255), truth / np.float32(255), None,
            name="teddy exact vs right, 0..1")
    compare(structural_similarity, warped / np.float32(255), truth / np.float32(255), None, mask,
            name="teddy exact vs right, 0..1, mask")
    # One channel.
    compare(structural_similarity, warped[..., 1] / np.float32(255), truth[..., 1] / np.float32(255), None, mask,
            name="teddy exact vs right, green, mask")


def test_noise(structural_similarity, noise):
    a, b, mask = noise
    compare(structural_similarity, a, b, None, name="noise float32 rgb")
    compare(structural_similarity, a, b, None, mask, name="noise float32 rgb, mask")
    compare(structural_similarity, a[..., 0], b[..., 0], 2.0, name="noise float32 grey, range 2")
    a8, b8 = (a * 255).astype(np.uint8), (b * 255).astype(np.uint8)
    compare(structural_similarity, a8, b8, None, name="noise uint8 rgb")
    compare(structural_similarity, a8, b8, None, mask, name="noise uint8 rgb, mask")
    compare(structural_similarity, a8[..., 2], b8[..., 2], 100.0, mask, name="noise uint8 grey, range 100, mask")


def test_the_data_range_matters(structural_similarity, noise):
    # The same images scored with the default range and with 255 differ, in both libraries alike:
    # the range is passed through, not replaced by a default.
    a, b, _ = noise
    default = compare(structural_similarity, a, b, None, name="noise, default range")
    wide = compare(structural_similarity, a, b, 255.0, name="noise, range 255")
    assert wide - default > 0.1


# ---- Views: any positive strides, read in place ----------------------------------------------

def test_strided_views_give_the_same_figures(noise):
    a, b, mask = noise
    planar_a = np.ascontiguousarray(a.transpose(2, 0, 1)).transpose(1, 2, 0)  # (H, W, C) over planes
    assert planar_a.strides[2] > planar_a.strides[0]
    assert metrics.ssim(planar_a, b) == metrics.ssim(a, b)
    assert metrics.psnr(planar_a, b, mask=mask) == metrics.psnr(a, b, mask=mask)
    # A crop with steps, and a channel sub-view: the copies give the same bits.
    view = a[3:80:2, 5:120:3, 1:]
    assert not view.flags.c_contiguous
    assert metrics.ssim(view, b[3:80:2, 5:120:3, 1:]) == metrics.ssim(np.ascontiguousarray(view),
                                                                      np.ascontiguousarray(b[3:80:2, 5:120:3, 1:]))
    # A bool mask and a uint8 one are the same; a mask that is a strided view too.
    assert metrics.ssim(a, b, mask=mask) == metrics.ssim(a, b, mask=mask.astype(np.uint8) * 9)
    big = np.zeros((97, 262), dtype=bool)
    big[:, ::2] = mask
    with pytest.raises(ValueError, match=r"mask: .*ascontiguousarray\(mask\)"):
        metrics.ssim(a, b, mask=big[:, ::2])


# ---- PSNR against NumPy ----------------------------------------------------------------------

def numpy_psnr(a, b, data_range, mask=None):
    d = a.astype(np.float64) - b.astype(np.float64)
    if mask is not None:
        d = d[mask]
    return 10.0 * np.log10(data_range * data_range / np.mean(d * d))


def test_psnr_matches_numpy(teddy_views, noise):
    right, left, warped, mask = teddy_views
    # The figure test_teddy.py prints for exact (peak 255, visible in both), and the whole frame.
    assert metrics.psnr(warped, right.astype(np.float32), mask=mask, data_range=255) == pytest.approx(
        teddy.score(warped, right, mask)[0], abs=1e-9)
    assert metrics.psnr(warped, right.astype(np.float32), data_range=255) == pytest.approx(
        numpy_psnr(warped, right, 255.0), abs=1e-9)
    assert metrics.psnr(left, right) == pytest.approx(numpy_psnr(left, right, 255.0), abs=1e-9)
    a, b, m = noise
    assert metrics.psnr(a, b) == pytest.approx(numpy_psnr(a, b, 1.0), abs=1e-9)
    assert metrics.psnr(a, b, mask=m, data_range=2.0) == pytest.approx(numpy_psnr(a, b, 2.0, m), abs=1e-9)
    assert metrics.psnr(a, a) == np.inf
    assert metrics.ssim(a, a) == pytest.approx(1.0, abs=1e-12)


# ---- Errors --------------------------------------------------------------------------------------

def test_errors_name_the_problem():
    a = np.zeros((20, 30, 3), dtype=np.float32)
    with pytest.raises(TypeError, match="a: expected a float32 or uint8 array, got float64"):
        metrics.ssim(a.astype(np.float64), a)
    with pytest.raises(TypeError, match="b: expected a float32 array like a"):
        metrics.psnr(a, a.astype(np.uint8))
    with pytest.raises(ValueError, match="a and b differ in shape"):
        metrics.psnr(a, a[:, :29])
    with pytest.raises(ValueError, match=r"expected an \(H, W\) or \(H, W, C\) array"):
        metrics.psnr(a[0, 0], a[0, 0])
    with pytest.raises(ValueError, match="window needs at least 11x11"):
        metrics.ssim(a[:10], a[:10])
    with pytest.raises(ValueError, match="nothing to score"):
        metrics.psnr(a[:0], a[:0])
    with pytest.raises(ValueError, match="data_range -1 must be finite and > 0"):
        metrics.ssim(a, a, data_range=-1)
    with pytest.raises(ValueError, match="data_range nan"):
        metrics.psnr(a, a, data_range=float("nan"))
    with pytest.raises(ValueError, match=r"a: .*cannot be read in place.*ascontiguousarray\(a\)"):
        metrics.ssim(a[::-1], a)
    with pytest.raises(ValueError, match=r"b: .*stride is negative or 0"):
        metrics.ssim(a, np.broadcast_to(np.float32(0.5), a.shape))
    with pytest.raises(TypeError, match="mask: expected a bool or uint8 array"):
        metrics.ssim(a, a, mask=np.ones((20, 30), dtype=np.int32))
    with pytest.raises(ValueError, match=r"mask: expected shape \(20, 30\)"):
        metrics.ssim(a, a, mask=np.ones((20, 30, 3), dtype=bool))
    with pytest.raises(ValueError, match="the mask has no pixel set"):
        metrics.psnr(a, a, mask=np.zeros((20, 30), dtype=bool))
    border = np.zeros((20, 30), dtype=bool)
    border[:5] = True
    with pytest.raises(ValueError, match="at least 5 pixels from the border"):
        metrics.ssim(a, a, mask=border)
    assert metrics.psnr(a, a, mask=border) == np.inf


def test_keywords_and_import():
    import importlib

    assert importlib.import_module("reproject.metrics") is reproject.metrics
    a = np.full((12, 12), 7, dtype=np.uint8)
    assert metrics.psnr(a=a, b=a, mask=None, data_range=None) == np.inf
    assert "structural_similarity" in metrics.ssim.__doc__


# ---- The GIL -------------------------------------------------------------------------------------

def test_two_threads_compute_at_once():
    # As test_gil.py proves for warp: with a rendezvous armed, each call waits inside the
    # GIL-released region until both are there; with the GIL held the second could not enter.
    rng = np.random.default_rng(5)
    a = rng.random((400, 600, 3), dtype=np.float32)
    b = rng.random((400, 600, 3), dtype=np.float32)
    results, errors = {}, []

    def call(name):
        try:
            results[name] = metrics.ssim(a, b)
        except Exception as e:  # reported by the assertion below
            errors.append(e)

    metrics._debug_reset_counters(rendezvous=2, timeout_seconds=60.0)
    try:
        threads = [threading.Thread(target=call, args=(name,)) for name in ("x", "y")]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        overlap = metrics._debug_max_concurrent_calls()
    finally:
        metrics._debug_reset_counters()
    assert not errors, errors
    assert overlap == 2
    assert results["x"] == results["y"]
