// Internal: one instruction set's kernels as a table of row functions (every stage of every
// method), and the declarations of the scalar references that fill the scalar tables and finish
// the SIMD twins' tails. kernels/scalar_table.cpp builds the scalar tables, kernels/simd_table.hpp
// a SIMD one; kernels/dispatch.hpp hands them out.
#pragma once

#include <cstdint>

#include "kernels/fma.hpp"
#include "kernels/frame.hpp"

namespace reproject::detail {

// A depth row in the frame's format; `stored` (null: not needed) receives the stored values d.
using DecodeRow = void (*)(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored);
using SearchRow = void (*)(const Frame& f, RowScratch& scratch);
using ResolveRow = void (*)(const Frame& f, int y, const RowScratch& scratch);
using NearestKey = float (*)(const Frame& f, const std::uint8_t* depth);  // max of key_far and s * p over a row
using SearchAndResolveRow = void (*)(const Frame& f, int y, RowScratch& scratch);

struct KernelTable {
  const char* name;
  DecodeRow decode;
  NearestKey nearest_key;
  SearchRow search[kMethodCount];
  ResolveRow resolve;
  // `single`'s search and the resolve in one pass over the row, the same bits as the two in turn;
  // null: the two in turn (the scalar tables).
  SearchAndResolveRow single_and_resolve;
  // `march16`'s search and the resolve in chunks of the row, the same bits as the two in turn;
  // null: the two in turn (the scalar tables).
  SearchAndResolveRow march16_and_resolve;
  // Sets with two ways to read the sRGB tables (kernels/color_formats.hpp SrgbLookup): the
  // faster on this processor, timed at its first call (kernels/color_formats_simd.hpp
  // faster_srgb_lookup). Null on the others: they gather.
  SrgbLookup (*srgb_lookup)();
};

// The scalar references are compiled twice (CMakeLists.txt): with the baseline flags, and with
// the AVX2 + FMA flags into namespace `host`, so that Arch::scalar on a CPU that has them runs
// single-instruction std::fma and std::floor instead of library calls (as a user's own scalar
// code built with -march=native would). Each translation unit sees its own copy as an inline
// namespace; the two copies give the same bits (-ffp-contract=off; fma and floor are exact).
#ifndef REPROJECT_SCALAR_COPY
#define REPROJECT_SCALAR_COPY baseline
#endif
inline namespace REPROJECT_SCALAR_COPY {

// Each method's scalar reference over target pixels [t_begin, t_end) of the current row: writes
// x (source columns) and the clipped flag per target pixel, which the resolve stage turns into
// outputs. (`exact` sweeps the whole row: it ignores the range.) Defined in kernels/<method>.cpp.
template <class Fma> void search_row_scanline(const Frame& f, RowScratch& scratch, int t_begin, int t_end);
template <class Fma> void search_row_march16(const Frame& f, RowScratch& scratch, int t_begin, int t_end);
template <class Fma> void search_row_single(const Frame& f, RowScratch& scratch, int t_begin, int t_end);
template <class Fma> void search_row_secant(const Frame& f, RowScratch& scratch, int t_begin, int t_end);
template <class Fma> void search_row_exact(const Frame& f, RowScratch& scratch, int t_begin, int t_end);

// Each method's .cpp instantiates its search for both FMA policies with this.
#define REPROJECT_INSTANTIATE_SEARCH(search)                            \
  template void search<Fused>(const Frame&, RowScratch&, int, int); \
  template void search<Unfused>(const Frame&, RowScratch&, int, int)

// The shared stages: decode columns [begin, end) of a row (no padding) and the frame's nearest
// key over them (kernels/decode.cpp); resolve target pixels [t_begin, t_end) of row y
// (kernels/resolve.cpp).
template <class Fma> void decode_parallax_columns(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored, int begin, int end);
template <class Fma> float nearest_key_in_columns(const Frame& f, const std::uint8_t* depth, int begin, int end, float nearest);
template <class Fma> void resolve_pixels(const Frame& f, int y, const RowScratch& scratch, int t_begin, int t_end);

// The scalar references as a table, with either FMA policy.
const KernelTable& scalar_kernels(bool fused);

}  // inline namespace REPROJECT_SCALAR_COPY

}  // namespace reproject::detail
