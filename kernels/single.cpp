// `single` (DESIGN §6): one point sample at the probe parallax (default: infinity, where the
// background comes from), re-projected with its own parallax.
#include "kernels/frame.hpp"

namespace reproject {
namespace detail {

void search_row_single(const Frame& f, RowScratch& scratch) {
  const float* parallax = scratch.parallax;
  const int probe_offset = point_offset(f.probe);
  for (int t = 0; t < f.target_width; ++t) {
    const int target = t + f.guard;
    const float surface = parallax[target + probe_offset];
    scratch.source_x[t] = static_cast<float>(target) - surface;
    scratch.clipped[t] = f.s * surface > f.key_near;  // the sample is nearer than allowed
  }
}

}  // namespace detail
}  // namespace reproject
