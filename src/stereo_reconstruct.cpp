// Screen -> view-space reconstruction (include/reproject/stereo.hpp, 4; docs/DESIGN.md §2, §3).
#include "reproject/stereo.hpp"

#include <cmath>

#include "kernels/fma.hpp"
#include "src/stereo_checks.hpp"

namespace reproject {

using detail::check_plane;
using detail::check_same_size;
using detail::in_function;
using detail::planes_overlap;

ViewPoint ScreenToView::at_pixel(float pixel_x, float pixel_y, float stored) const noexcept {
  // (l + u (r - l)) / n as one fused multiply-add on the pixel coordinate (u = (pixel + 0.5) / width
  // is folded into the bias), then one division by w: three roundings from the stored value to x.
  const float sx = detail::fused_madd(pixel_x, x_scale, x_bias);
  const float sy = detail::fused_madd(pixel_y, y_scale, y_bias);
  ViewPoint p;
  if (orthographic) {
    p.x = sx;
    p.y = sy;
    p.z = detail::fused_madd(stored, z_scale, z_bias);
  } else if (decoder.is_affine()) {
    const float w = decoder.inverse_depth(stored);
    p.x = sx / w;
    p.y = sy / w;
    p.z = 1.0f / w;
  } else {  // linear depth stores z itself
    p.x = sx * stored;
    p.y = sy * stored;
    p.z = stored;
  }
  return p;
}

Status make_screen_to_view(const ViewFrustum& frustum, DepthEncoding encoding, int width, int height,
                           ScreenToView* out) noexcept {
  const char* fn = "make_screen_to_view";
  if (out == nullptr) return Status(StatusCode::null_pointer, "%s: null output", fn);
  if (Status status = in_function(fn, frustum.validate()); !status.ok()) return status;
  if (width < 1 || height < 1)
    return Status(StatusCode::invalid_size, "%s: viewport %dx%d must be at least 1x1", fn, width, height);
  const double l = frustum.left, r = frustum.right, b = frustum.bottom, t = frustum.top;
  const double n = frustum.near_plane, f = frustum.far_plane;
  const double W = width, H = height;

  ScreenToView rec;
  rec.orthographic = frustum.orthographic;
  rec.width = width;
  rec.height = height;
  // u = (pixel_x + 0.5) / W: l + u (r - l) = (l + 0.5 (r - l) / W) + pixel_x (r - l) / W, and y
  // from the top edge t towards b. Perspective divides the edges by n (tangents); each constant is
  // rounded to float once.
  const double divisor = frustum.orthographic ? 1.0 : n;
  rec.x_scale = static_cast<float>((r - l) / W / divisor);
  rec.x_bias = static_cast<float>((l + 0.5 * (r - l) / W) / divisor);
  rec.y_scale = static_cast<float>((b - t) / H / divisor);
  rec.y_bias = static_cast<float>((t + 0.5 * (b - t) / H) / divisor);

  if (frustum.orthographic) {
    switch (encoding) {
      case DepthEncoding::linear:
        rec.z_scale = 1.0f;
        rec.z_bias = 0.0f;
        break;
      case DepthEncoding::standard:  // d = (z - n) / (f - n)
        rec.z_scale = static_cast<float>(f - n);
        rec.z_bias = static_cast<float>(n);
        break;
      case DepthEncoding::reversed:  // d = (f - z) / (f - n)
        rec.z_scale = static_cast<float>(-(f - n));
        rec.z_bias = static_cast<float>(f);
        break;
      case DepthEncoding::gl_ndc:  // d = (2 z - (f + n)) / (f - n)
        rec.z_scale = static_cast<float>(0.5 * (f - n));
        rec.z_bias = static_cast<float>(0.5 * (f + n));
        break;
      default:
        return Status(StatusCode::invalid_decoder,
                      "%s: an orthographic frustum stores z affinely: use linear, standard, reversed or gl_ndc, not %s",
                      fn, to_string(encoding));
    }
    if (!std::isfinite(rec.z_scale) || !std::isfinite(rec.z_bias))
      return Status(StatusCode::invalid_option, "%s: near %g, far %g overflow float", fn, n, f);
  } else {
    if (encoding == DepthEncoding::disparity)
      return Status(StatusCode::invalid_decoder, "%s: a disparity map gives no view-space depth", fn);
    rec.decoder = DepthDecoder::from_near_far(encoding, n, f);
    if (Status status = in_function(fn, rec.decoder.validate()); !status.ok()) return status;
  }
  if (!std::isfinite(rec.x_scale) || !std::isfinite(rec.x_bias) || !std::isfinite(rec.y_scale) ||
      !std::isfinite(rec.y_bias) || rec.x_scale == 0.0f || rec.y_scale == 0.0f)
    return Status(StatusCode::invalid_option, "%s: frustum edges / near give scales outside float range", fn);
  *out = rec;
  return Status();
}

Status screen_to_view(const ScreenToView& reconstruction, const FloatPlane& depth, const MutableFloatPlane& x,
                      const MutableFloatPlane& y, const MutableFloatPlane& z) noexcept {
  const char* fn = "screen_to_view";
  if (Status status = check_plane(depth, fn, "depth"); !status.ok()) return status;
  if (depth.width != reconstruction.width || depth.height != reconstruction.height)
    return Status(StatusCode::size_mismatch, "%s: depth is %dx%d, the reconstruction was made for %dx%d", fn,
                  depth.width, depth.height, reconstruction.width, reconstruction.height);
  const MutableFloatPlane* outputs[3] = {&x, &y, &z};
  static const char* const kNames[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    if (Status status = check_plane(*outputs[i], fn, kNames[i]); !status.ok()) return status;
    if (Status status = check_same_size(*outputs[i], depth, fn, kNames[i], "depth"); !status.ok()) return status;
    if (planes_overlap(*outputs[i], depth))
      return Status(StatusCode::aliasing, "%s: output %s overlaps the depth", fn, kNames[i]);
    for (int j = 0; j < i; ++j)
      if (planes_overlap(*outputs[i], *outputs[j]))
        return Status(StatusCode::aliasing, "%s: outputs %s and %s overlap", fn, kNames[j], kNames[i]);
  }
  if (!reconstruction.orthographic) {
    if (Status status = in_function(fn, reconstruction.decoder.validate()); !status.ok()) return status;
  }
  for (int row = 0; row < depth.height; ++row) {
    const float* d = depth.row(row);
    float* xr = x.row(row);
    float* yr = y.row(row);
    float* zr = z.row(row);
    const float pixel_y = static_cast<float>(row);
    for (int col = 0; col < depth.width; ++col) {
      const ViewPoint p = reconstruction.at_pixel(static_cast<float>(col), pixel_y, d[col]);
      xr[col] = p.x;
      yr[col] = p.y;
      zr[col] = p.z;
    }
  }
  return Status();
}

}  // namespace reproject
