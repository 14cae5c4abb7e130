// `single` (DESIGN §6): one point sample at the probe parallax (default: infinity, where the
// background comes from), re-projected with its own parallax.
// Its SIMD twin: kernels/single_simd.hpp.
#include "kernels/kernel_table.hpp"
#include "kernels/search.hpp"

namespace reproject::detail {
inline namespace REPROJECT_SCALAR_COPY {  // compiled twice (kernels/kernel_table.hpp)

template <class Fma>
void search_row_single(const Frame& f, RowScratch& scratch, int t_begin, int t_end) {
  const float* parallax = scratch.parallax;
  const int probe_offset = point_offset(f.probe);
  for (int t = t_begin; t < t_end; ++t) {
    const int target = t + f.guard;
    const float surface = parallax[target + probe_offset];
    scratch.source_x[t] = static_cast<float>(target) - surface;
    scratch.clipped[t] = f.s * surface > f.key_near;  // the sample is nearer than allowed
  }
}

REPROJECT_INSTANTIATE_SEARCH(search_row_single);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
