// The parallax budget of a depth buffer (include/reproject/stereo.hpp, 1; docs/DESIGN.md §4).
#include "reproject/stereo.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "src/memory.hpp"
#include "src/stereo_checks.hpp"

namespace reproject {
namespace {

using detail::check_camera;
using detail::check_depth_decoder;
using detail::check_plane;
using detail::kInf;
using detail::kNaN;
using detail::readable_inverse_depth;

// Linear interpolation between two order statistics. Equal neighbours give that value; an
// infinite one wins (its limit), where the formula would give inf - inf = NaN.
double interpolate(double low, double high, double fraction) noexcept {
  if (low == high || fraction == 0.0) return low;
  if (std::isinf(low)) return low;
  if (std::isinf(high)) return high;
  return low + fraction * (high - low);
}

}  // namespace

Status parallax_budget(const FloatPlane& depth, const DepthDecoder& decoder, const StereoCamera& camera,
                       const BudgetOptions& options, ParallaxBudget* out, std::int64_t* histogram) noexcept {
  const detail::CallScope scope;
  const char* fn = "parallax_budget";
  if (out == nullptr) return Status(StatusCode::null_pointer, "%s: null output", fn);
  if (Status status = check_plane(depth, fn, "depth"); !status.ok()) return status;
  if (Status status = check_depth_decoder(decoder, fn); !status.ok()) return status;
  if (Status status = check_camera(camera, fn); !status.ok()) return status;

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
  detail::Buffer<float> values;  // the library's allocator (reproject/memory.hpp)
  if (!values.reserve(static_cast<std::size_t>(count))) return detail::out_of_memory(fn, "the percentiles' values");

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
  float* begin = values.data();
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

}  // namespace reproject
