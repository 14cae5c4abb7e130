"""Image quality: PSNR and SSIM over NumPy arrays (float32 or uint8), computed by the library
(include/reproject/metrics.hpp, docs/QUALITY.md) with the GIL released."""
from ._reproject import metrics as _compiled
from ._signatures import forwards_to as _forwards_to

__all__ = ["psnr", "ssim"]

_debug_max_concurrent_calls = _compiled._debug_max_concurrent_calls
_debug_reset_counters = _compiled._debug_reset_counters


@_forwards_to(_compiled.psnr)
def psnr(a, b, mask=None, data_range=None):
    """Peak signal-to-noise ratio of a against b, in dB: 10 log10(data_range^2 / MSE), the mean
    squared difference over every channel of the scored pixels (all of them, or those where mask is
    true). +inf when the images are equal there, nan when a sample is nan or infinite.

    a, b: (H, W) or (H, W, C) arrays, both float32 or both uint8, of one shape, any positive
    strides (read in place).
    mask: None, or an (H, W) bool or uint8 array (nonzero: scored); it must select a pixel.
    data_range: the range of the values, finite and > 0 (None: 1.0 for float32, 255 for uint8).
    """


@_forwards_to(_compiled.ssim)
def ssim(a, b, mask=None, data_range=None):
    """Mean structural similarity (Wang et al. 2004), as scikit-image's structural_similarity
    computes it with gaussian_weights=True, sigma=1.5, use_sample_covariance=False and the same
    data_range: an 11 x 11 Gaussian window (sigma 1.5 pixels, truncated at 3.5 sigma), K1 = 0.01,
    K2 = 0.03, each channel's map averaged over the pixels at least 5 from the border (and where
    mask is true), then over the channels. Computed in float64 whatever the input; 1.0 for equal
    images.

    a, b: (H, W) or (H, W, C) arrays, both float32 or both uint8, of one shape (at least 11 x 11),
    any positive strides (read in place).
    mask: None, or an (H, W) bool or uint8 array (nonzero: scored); it must select a pixel at least
    5 from the border.
    data_range: the range of the values, finite and > 0 (None: 1.0 for float32, 255 for uint8).
    """
