// The checks that the functions of include/reproject/stereo.hpp share (src/stereo_checks.hpp).
#include "src/stereo_checks.hpp"

#include <cmath>

namespace reproject {
namespace detail {

Status in_function(const char* function, const Status& status) noexcept {
  if (status.ok()) return status;
  return Status(status.code(), "%s: %s", function, status.message());
}

Status check_camera(const StereoCamera& camera, const char* function) noexcept {
  if (!std::isfinite(camera.separation) || !(camera.separation >= 0.0))
    return Status(StatusCode::invalid_model, "%s: stereo separation %g must be finite and >= 0", function,
                  camera.separation);
  if (!std::isfinite(camera.convergence) || !(camera.convergence > 0.0))
    return Status(StatusCode::invalid_model, "%s: convergence %g must be finite and > 0", function,
                  camera.convergence);
  return Status();
}

Status check_depth_decoder(const DepthDecoder& decoder, const char* function) noexcept {
  if (Status status = in_function(function, decoder.validate()); !status.ok()) return status;
  if (decoder.encoding() == DepthEncoding::disparity)
    return Status(StatusCode::invalid_decoder, "%s: needs a depth encoding, not disparity (w = d is no inverse depth)",
                  function);
  return Status();
}

double readable_inverse_depth(const DepthDecoder& decoder, float stored, bool* unreadable) noexcept {
  const float w = decoder.inverse_depth(stored);
  *unreadable = !(w >= 0.0f);
  return *unreadable ? 0.0 : static_cast<double>(w);
}

}  // namespace detail
}  // namespace reproject
