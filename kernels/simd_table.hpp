// One instruction set's kernel table from the SIMD twins; included by kernels/arch_<set>.cpp only.
#pragma once

#include "kernels/decode_simd.hpp"
#include "kernels/exact_simd.hpp"
#include "kernels/march16_simd.hpp"
#include "kernels/resolve_simd.hpp"
#include "kernels/scanline_simd.hpp"
#include "kernels/secant_simd.hpp"
#include "kernels/single_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

template <class Arch, class Fma>
KernelTable make_simd_table(const char* name) {
  KernelTable table{};
  table.name = name;
  table.decode = simd_decode<Arch, Fma>;
  table.nearest_key = simd_nearest_key<Arch, Fma>;
  table.search[static_cast<int>(Method::scanline)] = simd_scanline<Arch, Fma>;
  table.search[static_cast<int>(Method::march16)] = simd_march16<Arch, Fma>;
  table.search[static_cast<int>(Method::single)] = simd_single<Arch, Fma>;
  table.search[static_cast<int>(Method::secant)] = simd_secant<Arch, Fma>;
  table.search[static_cast<int>(Method::exact)] = simd_exact<Arch, Fma>;
  table.resolve = simd_resolve<Arch, Fma>;
  table.fetch_mode_counts = fetch_modes_of_thread;
  return table;
}

}  // namespace
}  // namespace reproject::detail
