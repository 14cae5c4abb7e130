// `compare`'s scores of an output against the true eye (docs/CLI.md, docs/QUALITY.md): PSNR and
// MAE on the pixels visible in both views, PSNR and SSIM on the whole frame, with the library's
// metrics (include/reproject/metrics.hpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "reproject/reproject.hpp"

namespace reproject::cli {

struct Quality {
  double psnr = NAN, mae = NAN;                 // visible in both views (the mask); NaN when it is empty
  double psnr_frame = NAN, ssim_frame = NAN;    // every pixel, holes and off-source pixels as the options filled them
};

// `image` against `truth` (planar float images of one size, values 0..1: peak 1) over the colour
// channels, alpha ignored. `visible` holds one byte per pixel, nonzero where the pixel counts for
// the visible-in-both figures. SSIM is NaN for frames smaller than its 11 x 11 window.
Quality score(const Image& image, const Image& truth, const std::vector<std::uint8_t>& visible);

// The header line that says what the whole-frame figures include: every pixel, holes and pixels
// outside the source's view (exact's shares, in %) as `options` fill them.
std::string describe_whole_frame(const Options& options, double exact_hole, double exact_outside);

}  // namespace reproject::cli
