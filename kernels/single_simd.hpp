// SIMD twin of kernels/single.cpp (`single`).
#pragma once

#include "kernels/resolve_simd.hpp"
#include "kernels/search_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: search_row_single. Each vector's x and clipped flags from its one depth sample, in
// order of the vectors (next() after each): the search of simd_single, and the resolve's source
// of them when the two run as one pass (resolve_simd.hpp StoredSearch says the policy).
template <class Arch>
struct SingleProbe {
  using F = typename Lanes<Arch>::F;
  using B = typename Lanes<Arch>::B;
  // Locals, not f's or scratch's fields: the stores go through float pointers, which may alias
  // the Frame's floats, so fields would be reloaded after each store.
  const float* probe_row;  // lane t reads t + guard + the probe's offset
  float* source_x;
  float* clipped_flags;
  F s, key_near;
  F target;  // t + guard: exact small integers
  F surface;

  SingleProbe(const Frame& f, RowScratch& scratch)
      : probe_row(scratch.parallax + f.guard + point_offset(f.probe)),
        source_x(scratch.source_x.data()),
        clipped_flags(scratch.clipped.data()),
        s(f.s),
        key_near(f.key_near),
        target(F(static_cast<float>(f.guard)) + lane_offsets<Arch>()) {}

  REPROJECT_ALWAYS_INLINE F x(int t) {
    surface = F::load_unaligned(probe_row + t);
    return target - surface;
  }
  REPROJECT_ALWAYS_INLINE B clipped(int) const { return s * surface > key_near; }
  REPROJECT_ALWAYS_INLINE void keep(int t, const F& x_lanes, const B& clipped_lanes) const {
    x_lanes.store_unaligned(source_x + t);
    store_flags<Arch>(clipped_lanes, clipped_flags + t);
  }
  REPROJECT_ALWAYS_INLINE void next() { target = target + F(static_cast<float>(Lanes<Arch>::size)); }
};

template <class Arch, class Fma>
void simd_single(const Frame& f, RowScratch& scratch) {
  REPROJECT_LANE_TYPES(Arch);
  const int width = f.target_width;  // a local: the stores may alias f's fields
  SingleProbe<Arch> probe(f, scratch);
  int t = 0;
  for (; t + L <= width; t += L, probe.next()) {
    const F x = probe.x(t);
    probe.keep(t, x, probe.clipped(t));
  }
  search_row_single<Fma>(f, scratch, t, width);
}

// `single`'s search and the resolve as one pass over the row (KernelTable::single_and_resolve):
// the hit loop computes each vector's x and clipped flags itself (SingleProbe); the scalar search
// gives the tail's. The same bits as simd_single then simd_resolve.
template <class Arch, class Fma, class Tally = NoFetchTally>
void simd_single_and_resolve(const Frame& f, int y, RowScratch& scratch) {
  constexpr int L = Lanes<Arch>::size;
  search_row_single<Fma>(f, scratch, f.target_width / L * L, f.target_width);
  simd_resolve_with<Arch, Fma, Tally>(f, y, scratch, SingleProbe<Arch>(f, scratch));
}

}  // namespace
}  // namespace reproject::detail
