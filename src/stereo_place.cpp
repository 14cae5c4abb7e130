// 2D elements (cursor, label, HUD) placed at a depth in both eyes (include/reproject/stereo.hpp, 5;
// docs/DESIGN.md §4).
#include "reproject/stereo.hpp"

#include <cmath>

#include "src/stereo_checks.hpp"

namespace reproject {

using detail::check_camera;
using detail::check_depth_decoder;

Status place_at_depth(double ndc_x, double ndc_y, double z, const StereoCamera& camera, const DepthDecoder& decoder,
                      ClipPosition* left, ClipPosition* right) noexcept {
  const char* fn = "place_at_depth";
  if (left == nullptr && right == nullptr) return Status(StatusCode::null_pointer, "%s: both outputs are null", fn);
  if (!std::isfinite(ndc_x) || !std::isfinite(ndc_y))
    return Status(StatusCode::invalid_option, "%s: position (%g, %g) is not finite", fn, ndc_x, ndc_y);
  if (std::isnan(z) || !(z > 0.0))
    return Status(StatusCode::invalid_option, "%s: depth %g must be > 0 (+inf allowed)", fn, z);
  if (Status status = check_camera(camera, fn); !status.ok()) return status;
  if (Status status = check_depth_decoder(decoder, fn); !status.ok()) return status;

  // DESIGN §4: clip.x += side S (clip.w - c) at clip.w = z, then divided by w. At z = +inf, c/z = 0.
  const double shift = camera.separation * (1.0 - camera.convergence / z);
  const float stored = decoder.encode(z);
  const float y = static_cast<float>(ndc_y);
  if (left != nullptr) *left = ClipPosition{static_cast<float>(ndc_x - shift), y, stored, 1.0f};
  if (right != nullptr) *right = ClipPosition{static_cast<float>(ndc_x + shift), y, stored, 1.0f};
  return Status();
}

}  // namespace reproject
