// What is under a cursor, from both eyes' depth buffers (include/reproject/stereo.hpp, 3;
// docs/DESIGN.md §4, §5).
#include "reproject/stereo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "src/stereo_checks.hpp"

namespace reproject {
namespace {

using detail::check_plane;
using detail::check_same_size;
using detail::in_function;
using detail::kInf;
using detail::readable_inverse_depth;

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

// docs/DESIGN.md §5's exact search along the cursor's ray, in one eye: x(p) = u + e p/2 (e = -1 left,
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
  if (Status status = check_plane(left_depth, fn, "left depth"); !status.ok()) return status;
  if (Status status = check_plane(right_depth, fn, "right depth"); !status.ok()) return status;
  if (Status status = check_same_size(right_depth, left_depth, fn, "right depth", "left depth"); !status.ok()) return status;
  if (left_depth.width < 1 || left_depth.height < 1)
    return Status(StatusCode::invalid_size, "%s: depth planes are %dx%d: nothing to pick from", fn, left_depth.width,
                  left_depth.height);
  if (Status status = in_function(fn, decoder.validate()); !status.ok()) return status;
  if (Status status = in_function(fn, left_to_right.validate()); !status.ok()) return status;
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
  // caller's limit (docs/BEHAVIOUR.md "Parallax decode": p_near = s * max_negative_parallax), never
  // farther than a.
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

}  // namespace reproject
