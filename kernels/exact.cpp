// `exact` (DESIGN §5): the scalar table's forward sweep (kernels/exact.hpp).
// Its SIMD twin: kernels/exact_simd.hpp.
#include "kernels/exact.hpp"
#include "kernels/kernel_table.hpp"

namespace reproject::detail {
inline namespace REPROJECT_SCALAR_COPY {  // compiled twice (kernels/kernel_table.hpp)

template <class Fma>
void search_row_exact(const Frame& f, RowScratch& scratch, int, int) {
  sweep_row<Fma>(f, scratch);
}

REPROJECT_INSTANTIATE_SEARCH(search_row_exact);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
