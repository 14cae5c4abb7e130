// `march16` (DESIGN §6): march_steps + 1 point samples at equal parallax steps from p_near to
// p_far; the first sample on or behind the surface is re-projected with its own parallax.
// Its SIMD twin: kernels/march16_simd.hpp.
#include "kernels/kernel_table.hpp"
#include "kernels/search.hpp"

namespace reproject::detail {
inline namespace REPROJECT_SCALAR_COPY {  // compiled twice (kernels/kernel_table.hpp)

template <class Fma>
void search_row_march16(const Frame& f, RowScratch& scratch, int t_begin, int t_end) {
  const float* parallax = scratch.parallax;
  for (int t = t_begin; t < t_end; ++t) {
    const int target = t + f.guard;
    float x = static_cast<float>(target) - f.p_far;  // no hit: the far end
    bool clipped = false;
    for (int k = 0; k <= f.march_steps; ++k) {
      const float ray_parallax = madd<Fma>(static_cast<float>(k), f.march_step, f.p_near);
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

REPROJECT_INSTANTIATE_SEARCH(search_row_march16);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
