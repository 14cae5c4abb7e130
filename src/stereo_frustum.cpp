// View frusta and the one culling frustum of both eyes (include/reproject/stereo.hpp, 2;
// docs/DESIGN.md §4).
#include "reproject/stereo.hpp"

#include <cmath>

#include "src/stereo_checks.hpp"

namespace reproject {

using detail::check_camera;
using detail::in_function;
using detail::kNaN;

ViewFrustum ViewFrustum::perspective(double horizontal_fov, int width, int height, double near_plane,
                                     double far_plane) noexcept {
  ViewFrustum f;
  const double half_width = near_plane * std::tan(0.5 * horizontal_fov);
  const double half_height = height > 0 && width > 0 ? half_width * height / width : kNaN;
  f.left = -half_width;
  f.right = half_width;
  f.bottom = -half_height;
  f.top = half_height;
  f.near_plane = near_plane;
  f.far_plane = far_plane;
  return f;  // a bad fov or size leaves NaN or a reversed interval: validate() says so
}

Status ViewFrustum::validate() const noexcept {
  if (!std::isfinite(left) || !std::isfinite(right) || !(left < right))
    return Status(StatusCode::invalid_option, "frustum: left %g, right %g must be finite with left < right", left,
                  right);
  if (!std::isfinite(bottom) || !std::isfinite(top) || !(bottom < top))
    return Status(StatusCode::invalid_option, "frustum: bottom %g, top %g must be finite with bottom < top", bottom,
                  top);
  if (orthographic) {
    if (!std::isfinite(near_plane) || !std::isfinite(far_plane) || !(near_plane >= 0.0) || !(near_plane < far_plane))
      return Status(StatusCode::invalid_option,
                    "orthographic frustum: near %g, far %g must be finite with 0 <= near < far", near_plane, far_plane);
    return Status();
  }
  if (!std::isfinite(near_plane) || !(near_plane > 0.0) || std::isnan(far_plane) || !(far_plane > near_plane))
    return Status(StatusCode::invalid_option,
                  "perspective frustum: near %g, far %g must satisfy 0 < near < far (far may be +inf)", near_plane,
                  far_plane);
  return Status();
}

bool CullingFrustum::contains(double x, double y, double z, double slack) const noexcept {
  for (const auto& p : planes) {
    if (!(p[0] * x + p[1] * y + p[2] * z + p[3] >= -slack)) return false;
  }
  return true;
}

Status stereo_culling_frustum(const ViewFrustum& mono, const StereoCamera& camera, CullingFrustum* out) noexcept {
  const char* fn = "stereo_culling_frustum";
  if (out == nullptr) return Status(StatusCode::null_pointer, "%s: null output", fn);
  if (Status status = in_function(fn, mono.validate()); !status.ok()) return status;
  if (mono.orthographic)
    return Status(StatusCode::invalid_option, "%s: needs a perspective frustum (stereo eyes do not shear an "
                  "orthographic one)", fn);
  if (Status status = check_camera(camera, fn); !status.ok()) return status;

  const double S = camera.separation, c = camera.convergence, n = mono.near_plane, f = mono.far_plane;
  // Edge tangents of the mono frustum (x / z along each edge) and its half-width h: the eye with
  // side s has ndc_x = (2 x/z - (L + R)) / (R - L) + s S (1 - c/z), so its edges are
  // x = s T + (L - s S h) z and x = s T + (R - s S h) z with T = S h c.
  const double L = mono.left / n, R = mono.right / n, B = mono.bottom / n, T = mono.top / n;
  const double h = 0.5 * (R - L);
  // Z = c / (1 + 1/S), written so that S = 0 gives 0 rather than c / inf.
  const double Z = S * c / (1.0 + S);
  const double L_cull = L - S * h, R_cull = R + S * h;

  CullingFrustum cull;
  cull.pull_back = Z;
  cull.origin[0] = -Z * 0.5 * (L + R);
  cull.origin[1] = -Z * 0.5 * (B + T);
  cull.origin[2] = -Z;
  const double near_distance = n + Z, far_distance = f + Z;
  cull.frustum.left = L_cull * near_distance;
  cull.frustum.right = R_cull * near_distance;
  cull.frustum.bottom = B * near_distance;
  cull.frustum.top = T * near_distance;
  cull.frustum.near_plane = near_distance;
  cull.frustum.far_plane = far_distance;
  cull.frustum.orthographic = false;

  // Side planes through the culling origin o: x - o_x = tan (z - o_z) for each edge tangent,
  // oriented inwards and normalised.
  auto side = [&](double* plane, double sign, int axis, double tangent) {
    const double norm = std::sqrt(1.0 + tangent * tangent);
    const double o_axis = cull.origin[axis];
    plane[0] = axis == 0 ? sign / norm : 0.0;
    plane[1] = axis == 1 ? sign / norm : 0.0;
    plane[2] = -sign * tangent / norm;
    plane[3] = sign * (-o_axis + tangent * cull.origin[2]) / norm;
  };
  side(cull.planes[0], 1.0, 0, L_cull);   // left:   x - o_x - L' (z - o_z) >= 0
  side(cull.planes[1], -1.0, 0, R_cull);  // right:  R' (z - o_z) - (x - o_x) >= 0
  side(cull.planes[2], 1.0, 1, B);        // bottom
  side(cull.planes[3], -1.0, 1, T);       // top
  cull.planes[4][2] = 1.0;                // near: z - n >= 0
  cull.planes[4][3] = -n;
  if (std::isinf(f)) {
    cull.planes[5][3] = 1.0;  // no far plane: always inside
  } else {
    cull.planes[5][2] = -1.0;  // far: f - z >= 0
    cull.planes[5][3] = f;
  }
  *out = cull;
  return Status();
}

}  // namespace reproject
