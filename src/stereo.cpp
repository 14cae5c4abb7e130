// The stereo pipeline around reprojection (include/reproject/stereo.hpp; DESIGN.md §3, §4, §5).
#include "reproject/stereo.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>

#include "src/view_bounds.hpp"

namespace reproject {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A plane that may be empty (then its pointer is not needed); otherwise non-null, with a stride
// that holds its rows and an extent that fits the address space (view_bounds.hpp).
template <class T>
Status check_plane(const PlaneView<T>& plane, const char* function, const char* name) noexcept {
  if (plane.width < 0 || plane.height < 0)
    return Status(StatusCode::invalid_size, "%s: %s has a negative size %dx%d", function, name, plane.width,
                  plane.height);
  if (plane.width == 0 || plane.height == 0) return Status();
  if (plane.data == nullptr) return Status(StatusCode::null_pointer, "%s: %s data is null", function, name);
  char label[96];
  std::snprintf(label, sizeof label, "%s: %s", function, name);
  return detail::check_view_bytes(plane, 1, label, "elements");
}

template <class T, class U>
Status check_same_size(const PlaneView<T>& plane, const PlaneView<U>& reference, const char* function,
                       const char* name, const char* reference_name) noexcept {
  if (plane.width != reference.width || plane.height != reference.height)
    return Status(StatusCode::size_mismatch, "%s: %s is %dx%d, %s is %dx%d", function, name, plane.width,
                  plane.height, reference_name, reference.width, reference.height);
  return Status();
}

// Two checked planes share a byte of their rows (the bytes between rows are no one's: the halves
// of one side-by-side buffer do not overlap).
template <class T, class U>
bool planes_overlap(const PlaneView<T>& p, const PlaneView<U>& q) noexcept {
  return detail::views_touch(detail::view_bytes(p, 1), detail::view_bytes(q, 1));
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

// A decoder that yields inverse depth (not a disparity map, whose "w" is no depth).
Status check_depth_decoder(const DepthDecoder& decoder, const char* function) noexcept {
  const Status status = decoder.validate();
  if (!status.ok()) return Status(status.code(), "%s: %s", function, status.message());
  if (decoder.encoding() == DepthEncoding::disparity)
    return Status(StatusCode::invalid_decoder, "%s: needs a depth encoding, not disparity (w = d is no inverse depth)",
                  function);
  return Status();
}

// The inverse depth the kernels use for a stored value (BEHAVIOUR.md, parallax decode): values that
// decode to NaN or to w < 0 are farther than infinity, read as w = 0.
double readable_inverse_depth(const DepthDecoder& decoder, float stored, bool* unreadable) noexcept {
  const float w = decoder.inverse_depth(stored);
  *unreadable = !(w >= 0.0f);
  return *unreadable ? 0.0 : static_cast<double>(w);
}

// Linear interpolation between two order statistics. Equal neighbours give that value; an
// infinite one wins (its limit), where the formula would give inf - inf = NaN.
double interpolate(double low, double high, double fraction) noexcept {
  if (low == high || fraction == 0.0) return low;
  if (std::isinf(low)) return low;
  if (std::isinf(high)) return high;
  return low + fraction * (high - low);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// 1. Parallax budget

Status parallax_budget(const FloatPlane& depth, const DepthDecoder& decoder, const StereoCamera& camera,
                       const BudgetOptions& options, ParallaxBudget* out, std::int64_t* histogram) noexcept {
  const char* fn = "parallax_budget";
  if (out == nullptr) return Status(StatusCode::null_pointer, "%s: null output", fn);
  Status status = check_plane(depth, fn, "depth");
  if (!status.ok()) return status;
  if (!(status = check_depth_decoder(decoder, fn)).ok()) return status;
  if (!(status = check_camera(camera, fn)).ok()) return status;

  if (options.display_width < 0)
    return Status(StatusCode::invalid_option, "%s: display width %d must be >= 0 (0: the depth width)", fn,
                  options.display_width);
  const int W = options.display_width > 0 ? options.display_width : depth.width;
  const double E = options.eye_separation.value_or(camera.separation);
  if (!std::isfinite(E) || !(E > 0.0))
    return Status(StatusCode::invalid_option,
                  "%s: eye separation %g (interocular / screen width; unset: the camera's separation) must be "
                  "finite and > 0",
                  fn, E);
  const double eye_parallax = E * static_cast<double>(W);
  const double limit = options.parallax_limit.value_or(eye_parallax);
  if (!std::isfinite(limit) || !(limit >= 0.0))
    return Status(StatusCode::invalid_option, "%s: parallax limit %g px must be finite and >= 0", fn, limit);
  const int bins = options.histogram_bins;
  if (bins < 0 || bins > (1 << 24))
    return Status(StatusCode::invalid_option, "%s: histogram bins %d must be in 0..%d", fn, bins, 1 << 24);
  if (bins > 0 && histogram == nullptr)
    return Status(StatusCode::null_pointer, "%s: %d histogram bins asked for and the counts array is null", fn, bins);
  if (options.histogram_min.has_value() != options.histogram_max.has_value())
    return Status(StatusCode::invalid_option, "%s: give both histogram_min and histogram_max, or neither", fn);
  if (options.histogram_min.has_value()) {
    const double lo = *options.histogram_min, hi = *options.histogram_max;
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
      return Status(StatusCode::invalid_option, "%s: histogram range [%g, %g] must be finite with min < max", fn, lo,
                    hi);
  }

  ParallaxBudget budget;
  budget.display_width = W;
  budget.eye_separation = E;
  budget.eye_parallax = eye_parallax;
  budget.parallax_limit = limit;
  const std::int64_t count = static_cast<std::int64_t>(depth.width) * depth.height;
  budget.pixels = count;
  if (bins > 0) std::fill(histogram, histogram + bins, std::int64_t{0});
  if (count == 0) {
    budget.min = budget.max = budget.min_of_eyes = budget.max_of_eyes = kNaN;
    for (int i = 0; i < kBudgetPercentileCount; ++i) budget.percentile[i] = budget.percentile_of_eyes[i] = kNaN;
    budget.histogram_min = options.histogram_min.value_or(0.0);
    budget.histogram_max = options.histogram_max.value_or(1.0);
    *out = budget;
    return Status();
  }

  // Percentiles are order statistics: the values must be kept (one float each, once per call).
  std::unique_ptr<float[]> values(new (std::nothrow) float[static_cast<std::size_t>(count)]);
  if (!values)
    return Status(StatusCode::invalid_size, "%s: cannot allocate %lld floats for the percentiles", fn,
                  static_cast<long long>(count));

  // DESIGN §4 with sigma = +1 at the display width: p = a (1 - c w), a = S W. In double, so the
  // budget's own rounding is far below the decoder's.
  const double a = camera.separation * static_cast<double>(W), c = camera.convergence;
  const double w_near = 2.0 / c;            // z < c/2
  const double w_far = 1.0 / (100.0 * c);   // z > 100 c
  std::int64_t unreadable = 0, beyond = 0, nearer = 0, farther = 0, uncomfortable = 0;
  double min = kInf, max = -kInf, finite_min = kInf, finite_max = -kInf;
  std::size_t k = 0;
  for (int y = 0; y < depth.height; ++y) {
    const float* row = depth.row(y);
    for (int x = 0; x < depth.width; ++x) {
      bool bad = false;
      const double w = readable_inverse_depth(decoder, row[x], &bad);
      unreadable += bad;
      // w = +inf (linear depth 0) is infinitely near: p = -inf, unless S = 0 (then 0 * inf).
      const double p = std::isinf(w) ? (a > 0.0 ? -kInf : 0.0) : a * (1.0 - c * w);
      const bool is_beyond = std::fabs(p) > limit, is_nearer = w > w_near, is_farther = w < w_far;
      beyond += is_beyond;
      nearer += is_nearer;
      farther += is_farther;
      uncomfortable += is_beyond || is_nearer || is_farther;
      // Extremes, percentiles and bins all from the same float values, so that they agree.
      const float stored_p = static_cast<float>(p);
      min = std::min(min, static_cast<double>(stored_p));
      max = std::max(max, static_cast<double>(stored_p));
      if (std::isfinite(stored_p)) {
        finite_min = std::min(finite_min, static_cast<double>(stored_p));
        finite_max = std::max(finite_max, static_cast<double>(stored_p));
      }
      values[k++] = stored_p;
    }
  }
  const double n = static_cast<double>(count);
  budget.unreadable = unreadable;
  budget.beyond_limit = static_cast<double>(beyond) / n;
  budget.nearer_than_half_convergence = static_cast<double>(nearer) / n;
  budget.farther_than_100_convergence = static_cast<double>(farther) / n;
  budget.uncomfortable = static_cast<double>(uncomfortable) / n;
  budget.min = min;
  budget.max = max;

  // Ascending ranks: each nth_element works on what lies above the previous one.
  float* begin = values.get();
  float* end = begin + count;
  std::int64_t placed = -1;
  for (int i = 0; i < kBudgetPercentileCount; ++i) {
    const double rank = kBudgetPercentiles[i] / 100.0 * static_cast<double>(count - 1);
    const std::int64_t lo = static_cast<std::int64_t>(std::floor(rank));
    if (lo != placed) {
      std::nth_element(begin + (placed + 1), begin + lo, end);
      placed = lo;
    }
    const double fraction = rank - static_cast<double>(lo);
    double low = begin[lo], high = low;
    if (fraction > 0.0 && lo + 1 < count) high = *std::min_element(begin + lo + 1, end);
    budget.percentile[i] = interpolate(low, high, fraction);
  }
  budget.min_of_eyes = budget.min / eye_parallax;
  budget.max_of_eyes = budget.max / eye_parallax;
  for (int i = 0; i < kBudgetPercentileCount; ++i) budget.percentile_of_eyes[i] = budget.percentile[i] / eye_parallax;

  double lo = 0.0, hi = 1.0;
  if (options.histogram_min.has_value()) {
    lo = *options.histogram_min;
    hi = *options.histogram_max;
  } else if (finite_min <= finite_max) {
    lo = finite_min;
    hi = finite_max;
    if (!(lo < hi)) {  // flat content: one pixel wide around its value
      lo -= 0.5;
      hi += 0.5;
    }
  }
  budget.histogram_min = lo;
  budget.histogram_max = hi;
  if (bins > 0) {
    const double scale = static_cast<double>(bins) / (hi - lo);
    std::int64_t below = 0, above = 0;
    for (std::int64_t i = 0; i < count; ++i) {
      const double p = begin[i];
      if (p < lo) {
        ++below;
      } else if (p > hi) {
        ++above;
      } else {
        const int bin = std::min(bins - 1, static_cast<int>((p - lo) * scale));  // p == hi: the last, closed bin
        ++histogram[bin];
      }
    }
    budget.below_histogram = below;
    budget.above_histogram = above;
  }
  *out = budget;
  return Status();
}

// ---------------------------------------------------------------------------------------------
// Frusta

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

// ---------------------------------------------------------------------------------------------
// 2. Stereo culling frustum

bool CullingFrustum::contains(double x, double y, double z, double slack) const noexcept {
  for (const auto& p : planes) {
    if (!(p[0] * x + p[1] * y + p[2] * z + p[3] >= -slack)) return false;
  }
  return true;
}

Status stereo_culling_frustum(const ViewFrustum& mono, const StereoCamera& camera, CullingFrustum* out) noexcept {
  const char* fn = "stereo_culling_frustum";
  if (out == nullptr) return Status(StatusCode::null_pointer, "%s: null output", fn);
  Status status = mono.validate();
  if (!status.ok()) return Status(status.code(), "%s: %s", fn, status.message());
  if (mono.orthographic)
    return Status(StatusCode::invalid_option, "%s: needs a perspective frustum (stereo eyes do not shear an "
                  "orthographic one)", fn);
  if (!(status = check_camera(camera, fn)).ok()) return status;

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

// ---------------------------------------------------------------------------------------------
// 3. Picking

namespace {

enum class EyeAnswer : std::uint8_t { hit, wall, outside, clipped };

// One eye's row as the search reads it: parallax per column, linearly interpolated between pixel
// centres (exact for planes, since p is affine in w and w is linear in screen space, DESIGN §5),
// clamped to the edge values beyond the row.
struct EyeRow {
  const float* depth = nullptr;
  int width = 0;
  const DepthDecoder* decoder = nullptr;
  double a = 0.0, b = 0.0;
  double limit = 0.0;  // |p| beyond this is off every row the cursor can see: clamped (no infinities)

  double parallax_at_column(int j) const noexcept {
    bool unreadable = false;
    const double w = readable_inverse_depth(*decoder, depth[j], &unreadable);
    const double p = std::isinf(w) ? (b > 0.0 ? kInf : -kInf) : a + b * w;
    return std::min(limit, std::max(-limit, p));
  }
  double parallax_at(double x) const noexcept {
    if (width == 1 || !(x > 0.0)) return parallax_at_column(0);
    if (x >= width - 1) return parallax_at_column(width - 1);
    const int j = static_cast<int>(x);
    const double t = x - j;
    const double p0 = parallax_at_column(j), p1 = parallax_at_column(j + 1);
    return p0 + t * (p1 - p0);
  }
  // What this eye sees at x, for checking the other eye's answer: the interpolated surface, except
  // across a wall (a tear: |step| of p/2 above the hole threshold), where no pixel sees the
  // interpolated mix and the nearer of the two pixels is the most this eye can be hiding behind.
  double seen_at(double x, double s, double hole_threshold) const noexcept {
    if (width == 1 || !(x > 0.0)) return parallax_at_column(0);
    if (x >= width - 1) return parallax_at_column(width - 1);
    const int j = static_cast<int>(x);
    const double p0 = parallax_at_column(j), p1 = parallax_at_column(j + 1);
    if (0.5 * std::fabs(p1 - p0) > hole_threshold) return s * p0 >= s * p1 ? p0 : p1;
    return p0 + (x - j) * (p1 - p0);
  }
};

struct EyeSearch {
  EyeAnswer answer = EyeAnswer::hit;
  double parallax = 0.0;
};

// DESIGN §5's exact search along the cursor's ray, in one eye: x(p) = u + e p/2 (e = -1 left,
// +1 right), from p_near to p_far. g(p) = s (p - P(x(p))) > 0 while the ray is in front of the
// surface (s = sign b: s p grows towards the viewer). Samples at p_near, at every integer column the
// ray passes on the row (where P has its kinks), and at p_far: g is linear between samples, so the
// first sign change is intersected exactly.
EyeSearch search_eye(const EyeRow& row, double u, double e, double s, double p_near, double p_far,
                     double hole_threshold) noexcept {
  auto x_of = [&](double p) { return u + e * 0.5 * p; };
  auto g = [&](double p) { return s * (p - row.parallax_at(x_of(p))); };
  EyeSearch result;
  double p0 = p_near, g0 = g(p_near);
  if (g0 < 0.0) {
    result.answer = EyeAnswer::clipped;  // the surface is nearer than the search allows
    result.parallax = p_near;
    return result;
  }
  double crossing = p_near;
  if (g0 > 0.0) {
    const double x_start = x_of(p_near), x_end = x_of(p_far);
    const double direction = x_end >= x_start ? 1.0 : -1.0;
    // Integer columns strictly between the ends, within the row (beyond it P is constant: no kink).
    double k = direction > 0.0 ? std::floor(x_start) + 1.0 : std::ceil(x_start) - 1.0;
    if (direction > 0.0) k = std::max(k, 0.0);
    else k = std::min(k, static_cast<double>(row.width - 1));
    bool found = false;
    for (; direction > 0.0 ? (k < x_end && k <= row.width - 1) : (k > x_end && k >= 0.0); k += direction) {
      const double p1 = 2.0 * e * (k - u);  // x(p1) = k
      const double g1 = g(p1);
      if (g1 <= 0.0) {
        crossing = p0 + (p1 - p0) * (g0 / (g0 - g1));
        found = true;
        break;
      }
      p0 = p1;
      g0 = g1;
    }
    if (!found) {
      const double g1 = g(p_far);  // <= 0: nothing is farther than infinity
      crossing = g1 < 0.0 ? p0 + (p_far - p0) * (g0 / (g0 - g1)) : p_far;
    }
  }
  result.parallax = crossing;
  const double x = x_of(crossing);
  if (x < 0.0 || x > row.width - 1) {
    result.answer = EyeAnswer::outside;
  } else if (row.width > 1) {
    const int j = std::min(static_cast<int>(x), row.width - 2);
    // A wall: this eye's surface tears here (a silhouette), so the eye does not see the point on
    // the cursor's ray. Threshold on the eye->mono parallax p/2, as the kernels' hole threshold.
    const double step = 0.5 * std::fabs(row.parallax_at_column(j + 1) - row.parallax_at_column(j));
    if (step > hole_threshold) result.answer = EyeAnswer::wall;
  }
  return result;
}

}  // namespace

Status pick(const FloatPlane& left_depth, const FloatPlane& right_depth, const DepthDecoder& decoder,
            const ParallaxModel& left_to_right, double cursor_x, int cursor_y, const PickOptions& options,
            PickResult* out) noexcept {
  const char* fn = "pick";
  if (out == nullptr) return Status(StatusCode::null_pointer, "%s: null output", fn);
  Status status = check_plane(left_depth, fn, "left depth");
  if (!status.ok()) return status;
  if (!(status = check_plane(right_depth, fn, "right depth")).ok()) return status;
  if (!(status = check_same_size(right_depth, left_depth, fn, "right depth", "left depth")).ok()) return status;
  if (left_depth.width < 1 || left_depth.height < 1)
    return Status(StatusCode::invalid_size, "%s: depth planes are %dx%d: nothing to pick from", fn, left_depth.width,
                  left_depth.height);
  if (!(status = decoder.validate()).ok()) return Status(status.code(), "%s: %s", fn, status.message());
  if (!(status = left_to_right.validate()).ok()) return Status(status.code(), "%s: %s", fn, status.message());
  if (left_to_right.b == 0.0f)
    return Status(StatusCode::invalid_model, "%s: b = 0: parallax does not depend on depth, so nothing can be picked",
                  fn);
  if (!std::isfinite(cursor_x))
    return Status(StatusCode::invalid_option, "%s: cursor x %g is not finite", fn, cursor_x);
  if (cursor_y < 0 || cursor_y >= left_depth.height)
    return Status(StatusCode::invalid_option, "%s: cursor row %d is outside 0..%d", fn, cursor_y,
                  left_depth.height - 1);
  if (!std::isfinite(options.hole_threshold) || !(options.hole_threshold >= 0.0f))
    return Status(StatusCode::invalid_option, "%s: hole threshold %g must be finite and >= 0", fn,
                  static_cast<double>(options.hole_threshold));
  if (!std::isfinite(options.agreement) || !(options.agreement >= 0.0f))
    return Status(StatusCode::invalid_option, "%s: agreement %g must be finite and >= 0", fn,
                  static_cast<double>(options.agreement));
  if (options.max_negative_parallax.has_value() &&
      (!std::isfinite(*options.max_negative_parallax) || !(*options.max_negative_parallax >= 0.0f)))
    return Status(StatusCode::invalid_option, "%s: max negative parallax %g must be finite and >= 0", fn,
                  static_cast<double>(*options.max_negative_parallax));

  const int W = left_depth.width;
  const double a = left_to_right.a, b = left_to_right.b;
  const double s = b > 0.0 ? 1.0 : -1.0;
  // Beyond |p| = 2 (|u| + W + 1) a point is off both rows wherever it is: clamping there keeps the
  // march finite for infinitely near values (w = +inf) without changing any answer on the row.
  const double limit = 2.0 * (std::fabs(cursor_x) + W + 1.0) + std::fabs(a);
  EyeRow left_row{left_depth.row(cursor_y), W, &decoder, a, b, limit};
  EyeRow right_row{right_depth.row(cursor_y), W, &decoder, a, b, limit};

  // The far end is infinity (p = a); the near end the nearest parallax in either row, or the
  // caller's limit (BEHAVIOUR.md: p_near = s * max_negative_parallax), never farther than a.
  const double p_far = a;
  double near_key = s * p_far;
  if (options.max_negative_parallax.has_value()) {
    near_key = std::max(near_key, static_cast<double>(*options.max_negative_parallax));
  } else {
    for (int j = 0; j < W; ++j) {
      near_key = std::max(near_key, s * left_row.parallax_at_column(j));
      near_key = std::max(near_key, s * right_row.parallax_at_column(j));
    }
  }
  const double p_near = s * near_key;

  const EyeSearch left = search_eye(left_row, cursor_x, -1.0, s, p_near, p_far, options.hole_threshold);
  const EyeSearch right = search_eye(right_row, cursor_x, 1.0, s, p_near, p_far, options.hole_threshold);

  // Cross-check each eye's answer in the other eye's buffer. A point on the cursor's ray at
  // parallax p is at the other eye's column u -/+ p/2: the other eye sees either that point (the
  // same parallax) or something nearer hiding it, never something farther. An answer the other
  // eye contradicts lies on an interpolated step between an occluder and what is behind it (a
  // silhouette under the hole threshold) and is dropped. Off the other row there is nothing to check.
  auto confirmed = [&](const EyeSearch& answer, const EyeRow& other, double other_side) {
    if (answer.answer != EyeAnswer::hit) return false;
    const double x_other = cursor_x + other_side * 0.5 * answer.parallax;
    if (x_other < 0.0 || x_other > W - 1) return true;
    const double seen = other.seen_at(x_other, s, options.hole_threshold);
    return s * (seen - answer.parallax) >= -static_cast<double>(options.agreement);
  };
  const bool left_sees = confirmed(left, right_row, 1.0), right_sees = confirmed(right, left_row, -1.0);

  PickResult result;
  result.left_parallax = left.parallax;
  result.right_parallax = right.parallax;
  // Of two answers, the nearer (larger s p) is the first surface on the cursor's ray.
  const bool left_nearer = s * left.parallax >= s * right.parallax;
  double p = 0.0;
  if (left_sees && right_sees) {
    if (std::fabs(left.parallax - right.parallax) <= options.agreement) {
      result.source = PickSource::both;
      p = 0.5 * (left.parallax + right.parallax);
    } else {
      result.source = left_nearer ? PickSource::left : PickSource::right;
      p = left_nearer ? left.parallax : right.parallax;
    }
  } else if (left_sees || right_sees) {
    result.source = left_sees ? PickSource::left : PickSource::right;
    p = left_sees ? left.parallax : right.parallax;
  } else {
    result.source = PickSource::none;
    p = left_nearer ? left.parallax : right.parallax;
  }
  result.parallax = p;
  result.inverse_depth = (p - a) / b;
  result.depth = result.inverse_depth > 0.0 ? 1.0 / result.inverse_depth : kInf;
  result.left_x = cursor_x - 0.5 * p;
  result.right_x = cursor_x + 0.5 * p;
  *out = result;
  return Status();
}

// ---------------------------------------------------------------------------------------------
// 4. Screen -> view-space reconstruction

ViewPoint ScreenToView::at_pixel(float pixel_x, float pixel_y, float stored) const noexcept {
  // (l + u (r - l)) / n as one fused multiply-add on the pixel coordinate (u = (pixel + 0.5) / width
  // is folded into the bias), then one division by w: three roundings from the stored value to x.
  const float sx = std::fma(pixel_x, x_scale, x_bias);
  const float sy = std::fma(pixel_y, y_scale, y_bias);
  ViewPoint p;
  if (orthographic) {
    p.x = sx;
    p.y = sy;
    p.z = std::fma(stored, z_scale, z_bias);
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
  Status status = frustum.validate();
  if (!status.ok()) return Status(status.code(), "%s: %s", fn, status.message());
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
    status = rec.decoder.validate();
    if (!status.ok()) return Status(status.code(), "%s: %s", fn, status.message());
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
  Status status = check_plane(depth, fn, "depth");
  if (!status.ok()) return status;
  if (depth.width != reconstruction.width || depth.height != reconstruction.height)
    return Status(StatusCode::size_mismatch, "%s: depth is %dx%d, the reconstruction was made for %dx%d", fn,
                  depth.width, depth.height, reconstruction.width, reconstruction.height);
  const MutableFloatPlane* outputs[3] = {&x, &y, &z};
  static const char* const kNames[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    if (!(status = check_plane(*outputs[i], fn, kNames[i])).ok()) return status;
    if (!(status = check_same_size(*outputs[i], depth, fn, kNames[i], "depth")).ok()) return status;
    if (planes_overlap(*outputs[i], depth))
      return Status(StatusCode::aliasing, "%s: output %s overlaps the depth", fn, kNames[i]);
    for (int j = 0; j < i; ++j)
      if (planes_overlap(*outputs[i], *outputs[j]))
        return Status(StatusCode::aliasing, "%s: outputs %s and %s overlap", fn, kNames[j], kNames[i]);
  }
  if (!reconstruction.orthographic && !(status = reconstruction.decoder.validate()).ok())
    return Status(status.code(), "%s: %s", fn, status.message());
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

// ---------------------------------------------------------------------------------------------
// 5. 2D elements at a depth

Status place_at_depth(double ndc_x, double ndc_y, double z, const StereoCamera& camera, const DepthDecoder& decoder,
                      ClipPosition* left, ClipPosition* right) noexcept {
  const char* fn = "place_at_depth";
  if (left == nullptr && right == nullptr) return Status(StatusCode::null_pointer, "%s: both outputs are null", fn);
  if (!std::isfinite(ndc_x) || !std::isfinite(ndc_y))
    return Status(StatusCode::invalid_option, "%s: position (%g, %g) is not finite", fn, ndc_x, ndc_y);
  if (std::isnan(z) || !(z > 0.0))
    return Status(StatusCode::invalid_option, "%s: depth %g must be > 0 (+inf allowed)", fn, z);
  Status status = check_camera(camera, fn);
  if (!status.ok()) return status;
  if (!(status = check_depth_decoder(decoder, fn)).ok()) return status;

  // DESIGN §4: clip.x += side S (clip.w - c) at clip.w = z, then divided by w. At z = +inf, c/z = 0.
  const double shift = camera.separation * (1.0 - camera.convergence / z);
  const float stored = decoder.encode(z);
  const float y = static_cast<float>(ndc_y);
  if (left != nullptr) *left = ClipPosition{static_cast<float>(ndc_x - shift), y, stored, 1.0f};
  if (right != nullptr) *right = ClipPosition{static_cast<float>(ndc_x + shift), y, stored, 1.0f};
  return Status();
}

// ---------------------------------------------------------------------------------------------
// 6. Halo-reduction pre-filter

Status dilate_nearer_depth(const FloatPlane& depth, const DepthDecoder& decoder, int radius,
                           const MutableFloatPlane& out) noexcept {
  const char* fn = "dilate_nearer_depth";
  Status status = check_plane(depth, fn, "depth");
  if (!status.ok()) return status;
  if (!(status = check_plane(out, fn, "output")).ok()) return status;
  if (!(status = check_same_size(out, depth, fn, "output", "depth")).ok()) return status;
  if (planes_overlap(out, depth)) return Status(StatusCode::aliasing, "%s: output overlaps the depth", fn);
  if (!(status = decoder.validate()).ok()) return Status(status.code(), "%s: %s", fn, status.message());
  if (radius < 0) return Status(StatusCode::invalid_option, "%s: radius %d must be >= 0", fn, radius);

  const int width = depth.width;
  // Larger w is nearer for every encoding (DESIGN §3); unreadable values (NaN, w < 0) rank below
  // everything so they never spread.
  auto key = [&](float stored) {
    const float w = decoder.inverse_depth(stored);
    return w >= 0.0f ? w : -std::numeric_limits<float>::infinity();
  };
  for (int y = 0; y < depth.height; ++y) {
    const float* in = depth.row(y);
    float* dst = out.row(y);
    // Sliding window maximum with the leftmost winner kept: when the winner leaves the window the
    // window is rescanned, otherwise only the entering pixel can beat it. O(width) on typical
    // content, O(width * radius) at worst; no scratch.
    int best = -1;
    float best_key = 0.0f;
    for (int x = 0; x < width; ++x) {
      const int lo = std::max(0, x - radius);
      const int hi = static_cast<int>(std::min<std::int64_t>(width - 1, static_cast<std::int64_t>(x) + radius));
      if (best < lo) {
        best = lo;
        best_key = key(in[lo]);
        for (int j = lo + 1; j <= hi; ++j) {
          const float k = key(in[j]);
          if (k > best_key) {
            best = j;
            best_key = k;
          }
        }
      } else {
        const float k = key(in[hi]);
        if (k > best_key) {
          best = hi;
          best_key = k;
        }
      }
      // A window of only unreadable values keeps the pixel's own value.
      dst[x] = best_key == -std::numeric_limits<float>::infinity() ? in[x] : in[best];
    }
  }
  return Status();
}

}  // namespace reproject
