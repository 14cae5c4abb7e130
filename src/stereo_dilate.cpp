// The halo-reduction pre-filter: horizontal dilation of the nearer depth
// (include/reproject/stereo.hpp, 6; docs/DESIGN.md §3).
#include "reproject/stereo.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "src/stereo_checks.hpp"

namespace reproject {

using detail::check_plane;
using detail::check_same_size;
using detail::in_function;
using detail::planes_overlap;

Status dilate_nearer_depth(const FloatPlane& depth, const DepthDecoder& decoder, int radius,
                           const MutableFloatPlane& out) noexcept {
  const char* fn = "dilate_nearer_depth";
  if (Status status = check_plane(depth, fn, "depth"); !status.ok()) return status;
  if (Status status = check_plane(out, fn, "output"); !status.ok()) return status;
  if (Status status = check_same_size(out, depth, fn, "output", "depth"); !status.ok()) return status;
  if (planes_overlap(out, depth)) return Status(StatusCode::aliasing, "%s: output overlaps the depth", fn);
  if (Status status = in_function(fn, decoder.validate()); !status.ok()) return status;
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
