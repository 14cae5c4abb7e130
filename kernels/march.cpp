// `march16` (DESIGN §6): march_steps + 1 point samples at equal parallax steps from p_near to
// p_far; the first sample on or behind the surface is re-projected with its own parallax.
#include "kernels/frame.hpp"

namespace reproject {
namespace detail {

void search_row_march(const Frame& f, RowScratch& scratch) {
  const float* parallax = scratch.parallax;
  for (int t = 0; t < f.target_width; ++t) {
    const int target = t + f.guard;
    float x = static_cast<float>(target) - f.p_far;  // no hit: the far end
    bool clipped = false;
    for (int k = 0; k <= f.march_steps; ++k) {
      const float ray_parallax = std::fma(static_cast<float>(k), f.march_step, f.p_near);
      const float surface = parallax[target + point_offset(ray_parallax)];
      if (f.s * surface >= f.s * ray_parallax) {  // on or behind
        x = static_cast<float>(target) - surface;
        clipped = k == 0 && f.s * surface > f.key_near;
        break;
      }
    }
    scratch.source_x[t] = x;
    scratch.clipped[t] = clipped;
  }
}

}  // namespace detail
}  // namespace reproject
