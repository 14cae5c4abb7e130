// The scalar references as kernel tables, one per FMA policy: the whole-row functions the row
// driver calls (kernels/kernel_table.hpp). Compiled twice, like every scalar reference.
#include "kernels/kernel_table.hpp"

namespace reproject::detail {
inline namespace REPROJECT_SCALAR_COPY {
namespace {

// The scalar references as whole-row kernels.
template <class Fma>
void scalar_decode(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored) {
  decode_parallax_columns<Fma>(f, depth, parallax, stored, 0, f.source_width);
}
template <class Fma>
float scalar_nearest_key(const Frame& f, const std::uint8_t* depth) {
  return nearest_key_in_columns<Fma>(f, depth, 0, f.source_width, f.key_far);
}
template <class Fma, void (*Search)(const Frame&, RowScratch&, int, int)>
void scalar_search(const Frame& f, RowScratch& scratch) {
  Search(f, scratch, 0, f.target_width);
}
template <class Fma>
void scalar_resolve(const Frame& f, int y, const RowScratch& scratch) {
  resolve_pixels<Fma>(f, y, scratch, 0, f.target_width);
}
template <class Fma>
KernelTable make_scalar_table(const char* name) {
  KernelTable table{};
  table.name = name;
  table.decode = scalar_decode<Fma>;
  table.nearest_key = scalar_nearest_key<Fma>;
  table.search[static_cast<int>(Method::scanline)] = scalar_search<Fma, search_row_scanline<Fma>>;
  table.search[static_cast<int>(Method::march16)] = scalar_search<Fma, search_row_march16<Fma>>;
  table.search[static_cast<int>(Method::single)] = scalar_search<Fma, search_row_single<Fma>>;
  table.search[static_cast<int>(Method::secant)] = scalar_search<Fma, search_row_secant<Fma>>;
  table.search[static_cast<int>(Method::exact)] = scalar_search<Fma, search_row_exact<Fma>>;
  table.resolve = scalar_resolve<Fma>;
  return table;
}

}  // namespace

const KernelTable& scalar_kernels(bool fused) {
  static const KernelTable fused_table = make_scalar_table<Fused>("scalar");
  static const KernelTable unfused_table = make_scalar_table<Unfused>("scalar-unfused");
  return fused ? fused_table : unfused_table;
}

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
