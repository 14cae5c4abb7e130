// `scanline` (DESIGN §6): from the near end, one source column a step to the far end; the first
// sample on or behind the surface ends the march and the crossing is intersected linearly with
// the previous sample. Samples sit on every integer column in between, so each bracket lies on
// one linear piece of the surface: exact to rounding inside the allowed range. O(range).
// Its SIMD twin: kernels/scanline_simd.hpp.
#include "kernels/kernel_table.hpp"
#include "kernels/search.hpp"

namespace reproject::detail {
inline namespace REPROJECT_SCALAR_COPY {  // compiled twice (kernels/kernel_table.hpp)

template <class Fma>
void search_row_scanline(const Frame& f, RowScratch& scratch, int t_begin, int t_end) {
  const float* parallax = scratch.parallax;
  const float o_near = -f.p_near;
  const float o_far = -f.p_far;
  for (int t = t_begin; t < t_end; ++t) {
    const int target = t + f.guard;
    const float gap_near = gap_at_offset(f, o_near, parallax_at_offset<Fma>(parallax, target, o_near));
    scratch.clipped[t] = gap_near < 0.0f;
    // Behind at the near end: clipped; exactly on: a hit there.
    const float offset = gap_near <= 0.0f ? o_near : march_columns<Fma>(f, parallax, target, o_near, gap_near, o_far);
    scratch.source_x[t] = static_cast<float>(target) + offset;
  }
}

REPROJECT_INSTANTIATE_SEARCH(search_row_scanline);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
