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

// The xsimd architecture and FMA policy of each instruction set's table: the library's
// (kernels/arch_<set>.cpp) and the tests' counting copies (tests/arch_layer/) alike.
template <Arch Set> struct InstructionSet;
template <> struct InstructionSet<Arch::sse> { using arch = xsimd::sse4_1; using fma = Unfused; };
template <> struct InstructionSet<Arch::avx2> { using arch = xsimd::fma3<xsimd::avx2>; using fma = Fused; };
template <> struct InstructionSet<Arch::avx512> { using arch = xsimd::avx512bw; using fma = Fused; };
template <> struct InstructionSet<Arch::neon> { using arch = xsimd::neon64; using fma = Fused; };

// `Tally` hears the resolve's column-fetch modes (kernels/simd.hpp): NoFetchTally in the library.
template <Arch Set, class Tally = NoFetchTally>
KernelTable make_simd_table(const char* name) {
  using Arch = typename InstructionSet<Set>::arch;
  using Fma = typename InstructionSet<Set>::fma;
  KernelTable table{};
  table.name = name;
  table.decode = simd_decode<Arch, Fma>;
  table.nearest_key = simd_nearest_key<Arch, Fma>;
  table.search[static_cast<int>(Method::scanline)] = simd_scanline<Arch, Fma>;
  table.search[static_cast<int>(Method::march16)] = simd_march16<Arch, Fma>;
  table.search[static_cast<int>(Method::single)] = simd_single<Arch, Fma>;
  table.search[static_cast<int>(Method::secant)] = simd_secant<Arch, Fma>;
  table.search[static_cast<int>(Method::exact)] = simd_exact<Arch, Fma>;
  table.resolve = simd_resolve<Arch, Fma, Tally>;
  table.single_and_resolve = simd_single_and_resolve<Arch, Fma, Tally>;
  table.march16_and_resolve = simd_march16_and_resolve<Arch, Fma, Tally>;
  if constexpr (has_srgb_permutes<Arch>()) table.srgb_lookup = faster_srgb_lookup<Arch, Fma>;
  return table;
}

}  // namespace
}  // namespace reproject::detail
