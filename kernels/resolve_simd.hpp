// Internal: SIMD twin of kernels/resolve.cpp, the resolve stage every method shares
// (docs/DESIGN.md §6 "One resolve stage for all").
//
// A row's vectors take one of two paths. Nearly all of them, on any scene, are plain: every lane's source
// x lies in the row, and every lane is a hit, clipped, or a hole whose fill is written. Those run a loop
// compiled once per colour path and with or without the depth output (resolve_hits), with nothing in it
// that only the rare vectors need. A vector with any other lane (outside, or a hole left unwritten by
// HoleFill::none) goes to resolve_vector, the general case, which handles every mix; for the plain lanes
// it computes exactly what the hit loop computes, so a vector's bits do not depend on its path.
#pragma once

#include <algorithm>

#include "kernels/resolve_row_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// The lanes in `hole` of j0, j1 and frac moved to the hole's fill column at weight 0 (both columns
// the fill column, so any blend gives its values): of j0 and j1, a wall's farther endpoint (DESIGN
// §5: the smaller key s * p), or with HoleFill::foreground its nearer one. Returns the lanes whose
// fill column is j1. Both paths fill holes through this (resolve_vector, WriteHits).
template <class Arch>
REPROJECT_ALWAYS_INLINE inline xsimd::batch_bool<float, Arch> move_holes_to_fill(
    const RowContext<Arch>& row, const xsimd::batch<float, Arch>& p0, const xsimd::batch<float, Arch>& p1,
    const xsimd::batch_bool<float, Arch>& hole, xsimd::batch<float, Arch>& j0, xsimd::batch<float, Arch>& j1,
    xsimd::batch<float, Arch>& frac) {
  using F = xsimd::batch<float, Arch>;
  const auto j1_farther = row.s * p1 < row.s * p0;
  const auto second = row.fill_foreground ? ~j1_farther : j1_farther;
  const F fill = xsimd::select(second, j1, j0);
  j0 = xsimd::select(hole, fill, j0);
  j1 = xsimd::select(hole, fill, j1);
  frac = xsimd::select(hole, F(0.0f), frac);
  return second;
}

// A column fetch whose lanes in `hole` read both columns at the fill column (j0's or j1's, as
// `second` says) instead, as resolve_vector's fetch does once it has moved a hole's columns there:
// the same values, from the columns the hit loop already planned. Its lanes are no longer
// consecutive pixels, so it is not the consecutive mode to the colour blends.
template <class Arch, class Fetch>
struct FillingFetch {
  using F = typename Lanes<Arch>::F;
  using B = typename Lanes<Arch>::B;
  static constexpr auto mode = ColumnFetch<Arch>::Mode::gather;
  const Fetch& fetch;
  B hole, second;
  REPROJECT_ALWAYS_INLINE void operator()(const float* row, F& at_first, F& at_second) const {
    fetch(row, at_first, at_second);
    const F fill = xsimd::select(second, at_second, at_first);
    at_first = xsimd::select(hole, fill, at_first);
    at_second = xsimd::select(hole, fill, at_second);
  }
};

// Target pixels [t, t + L) whatever their lanes hold (scalar twin: resolve_pixels), for the row's
// colour path. `tally` hears the fetch mode of every vector (kernels/simd.hpp, NoFetchTally).
template <ColorPath Path, class Arch, class Fma, class Tally>
REPROJECT_NOINLINE void resolve_vector(const RowContext<Arch>& row, int t, Tally& tally) {
  REPROJECT_LANE_TYPES(Arch);
  const F zero(0.0f), one(1.0f);
  const F x = F::load_unaligned(row.source_x + t);
  const B clipped = load_flags<Arch>(row.clipped + t);
  const B outside = ((x < zero) | (x > row.last)) & ~clipped;
  F xs = x;
  if (row.mirror_edges) {  // reflected about the edge pixel's centre (then clamped)
    xs = xsimd::select(outside & (x < zero), -x, xsimd::select(outside & (x > row.last), (row.last - x) + row.last, x));
  }
  const F xc = vmin(vmax(xs, zero), row.last);  // == x in the row
  F j0 = vfloor(xc);
  F j1 = vmin(j0 + one, row.last);
  F frac = xc - j0;
  // Every column read below lies in [j0, j1] (a fill picks one of the two).
  ColumnFetch<Arch> columns(j0, j1, row.source_width);
  tally.add(static_cast<int>(columns.mode()));
  F p0, p1;
  columns.fetch(row.parallax, p0, p1);
  const B hole = ((p1 - p0) > row.tau) & ~(clipped | outside);
  const bool any_hole = xsimd::any(hole);
  if (any_hole) {
    move_holes_to_fill<Arch>(row, p0, p1, hole, j0, j1, frac);
    columns.bind(j0, j1);
    tally.add(static_cast<int>(columns.mode()));
  }
  // Lanes whose colour and depth are left to the caller keep the target's values.
  const bool masked = (!row.edges_written && xsimd::any(outside)) || (!row.holes_written && any_hole);
  const B write = ~((outside & B(!row.edges_written)) | (hole & B(!row.holes_written)));
  const B black = outside & B(row.black_edges);
  const bool any_black = row.black_edges && xsimd::any(black);
  columns.visit([&](const auto& fetch) {
    write_color<Path, Arch, Fma>(row, fetch, t, j0, j1, frac, write, black, masked, any_black);
    if (row.depth_out) write_depth<Arch, Fma>(row, fetch, t, frac, write, masked);
  });
  if (row.status_out) {
    store_bytes<Arch>(xsimd::select(clipped, F(3.0f), xsimd::select(outside, F(2.0f), xsimd::select(hole, one, zero))),
                      row.status_out + t);
  }
  if (row.x_out) x.store_unaligned(row.x_out + t);
}

// The hit loop's body for one vector and one column fetch (ColumnFetch::plan_next_and_visit):
// the columns' parallax, then the colour and depth of pixels [t, t + L) (every lane written, none
// black), and `holes` set to the lanes that are holes. A hole here is one whose fill is written
// (HoleFill::none leaves its lanes to the caller: false, and the vector goes to resolve_vector):
// its lanes read both columns at the fill column and blend them at weight 0, as resolve_vector
// does. A functor so that it can be forced inline: GCC kept an equivalent lambda out of line, and
// the call per vector passed its vector arguments through memory (docs/PERFORMANCE.md, "Measured
// design choices").
template <ColorPath Path, bool WithDepth, class Arch, class Fma, class Tally, class Search>
struct WriteHits {
  using F = typename Lanes<Arch>::F;
  using B = typename Lanes<Arch>::B;
  const RowContext<Arch>& row;
  Tally& tally;
  const Search& search;  // the vector's clipped flags, asked for only at a wall (most vectors have none)
  int t;
  F j0, frac;
  B& holes;

  template <class Fetch>
  REPROJECT_ALWAYS_INLINE bool operator()(const Fetch& fetch) const {
    F p0, p1;
    fetch(row.parallax, p0, p1);
    const B wall = (p1 - p0) > row.tau;  // a lane at a wall is a hole unless clipped
    B hole(false);
    bool any_hole = false;
    if (xsimd::any(wall)) {
      hole = wall & ~search.clipped(t);
      any_hole = xsimd::any(hole);
    }
    if (any_hole && !row.holes_written) return false;
    tally.add(static_cast<int>(Fetch::mode));
    prefetch_next_row<Path>(row, t);
    F first = j0, second = vmin(j0 + F(1.0f), row.last), weight = frac;  // second: read by the pixel paths and holes only
    if (!any_hole) {
      holes = B(false);
      write(fetch, first, second, weight);
      return true;
    }
    const B fill_second = move_holes_to_fill<Arch>(row, p0, p1, hole, first, second, weight);
    write(FillingFetch<Arch, Fetch>{fetch, hole, fill_second}, first, second, weight);
    holes = hole;
    return true;
  }

  template <class Fetch>
  REPROJECT_ALWAYS_INLINE void write(const Fetch& fetch, const F& first, const F& second, const F& weight) const {
    const B none(false);
    write_color<Path, Arch, Fma>(row, fetch, t, first, second, weight, ~none, none, false, false);
    if constexpr (WithDepth) write_depth<Arch, Fma>(row, fetch, t, weight, ~none, false);
  }
};

// Where the hit loop takes each vector's x and clipped flags from: the rows the search stage
// wrote into the scratch (StoredSearch), or, for `single`, computed in the loop (SingleProbe,
// kernels/single_simd.hpp: no pass of its own, no stores and loads between the stages). A policy
// gives x(t), then clipped(t) as often as asked (not at all for a vector with no wall that stays in
// the hit loop and writes no status: most vectors); keep(t, x, clipped) before a vector goes to
// resolve_vector (which reads the scratch); next() after every vector, in order.
template <class Arch>
struct StoredSearch {
  const float* source_x;
  const float* clipped_flags;
  REPROJECT_ALWAYS_INLINE auto x(int t) const { return Lanes<Arch>::F::load_unaligned(source_x + t); }
  REPROJECT_ALWAYS_INLINE auto clipped(int t) const { return load_flags<Arch>(clipped_flags + t); }
  template <class X, class C> REPROJECT_ALWAYS_INLINE void keep(int, const X&, const C&) const {}  // stored
  REPROJECT_ALWAYS_INLINE void next() const {}
};

// The row's vectors of target pixels [begin, end) (multiples of L), each either plain (hits, clipped lanes and written holes in
// the row), done here, or handed to resolve_vector. For plain lanes resolve_vector computes the same:
// nothing is outside, so xs = x, the clamp leaves x, a clipped lane is never a hole, a hole's columns both
// become its fill column at weight 0 (FillingFetch), no lane is masked or black, and the status is hit (0),
// hole (1) or clipped (3). (Out of line, one call per row or chunk of one: so that each path's loop is a function of its
// own in profiles and instruction counts, bench/instruction_count.py, whatever the compiler would inline.)
template <ColorPath Path, bool WithDepth, class Arch, class Fma, class Tally, class Search>
REPROJECT_NOINLINE void resolve_hits(const RowContext<Arch>& whole_row, int begin, int end, Tally& tally, Search search) {
  REPROJECT_LANE_TYPES(Arch);
  // A copy the compiler can keep in registers: the stores below go through byte pointers, which
  // may alias anything, so fields read through a reference would be reloaded after each of them.
  const RowContext<Arch> row = whole_row;
  const F zero(0.0f);
  // x in [0, last >= 0] on its bits, as unsigned integers (compared as signed ones with the top bit
  // flipped): floats >= +0 order as their bits do; a negative one, -0 too, and a NaN fall outside
  // (-0 then takes the general path, whose clamp gives it the same bits as here).
  const I top_bit(INT32_MIN), last_key = bits_of<Arch>(row.last) ^ top_bit;
  const bool extras = row.status_out || row.x_out;  // one test per vector when neither is asked for
  ColumnFetch<Arch> columns(row.source_width);
  for (int t = begin; t < end; t += L, search.next()) {
    const F x = search.x(t);
    if (xsimd::any((bits_of<Arch>(x) ^ top_bit) > last_key)) {
      search.keep(t, x, search.clipped(t));
      resolve_vector<Path, Arch, Fma>(whole_row, t, tally);
      continue;
    }
    const F j0 = vfloor(x);
    const F frac = x - j0;
    B holes;
    if (!columns.plan_next_and_visit(j0, row.last,
                                     WriteHits<Path, WithDepth, Arch, Fma, Tally, Search>{row, tally, search, t, j0, frac, holes})) {
      search.keep(t, x, search.clipped(t));
      resolve_vector<Path, Arch, Fma>(whole_row, t, tally);
      continue;
    }
    if (!extras) continue;
    if (row.status_out) {
      store_bytes<Arch>(xsimd::select(search.clipped(t), F(3.0f), xsimd::select(holes, F(1.0f), zero)), row.status_out + t);
    }
    if (row.x_out) x.store_unaligned(row.x_out + t);
  }
}

template <ColorPath Path, class Arch, class Fma, class Tally, class Search>
void resolve_hits_of_path(const RowContext<Arch>& row, int begin, int end, Tally& tally, const Search& search) {
  if (row.depth_out) resolve_hits<Path, true, Arch, Fma>(row, begin, end, tally, search);
  else resolve_hits<Path, false, Arch, Fma>(row, begin, end, tally, search);
}

// Row y's resolve in chunks of `chunk` target pixels (a multiple of L): search_vectors(begin, end)
// then the resolve of each chunk's vectors, the vectors' x and clipped flags from `search`; then
// search_tail(whole, width) and the tail's pixels (scalar twin: resolve_pixels). A search that
// carries state from vector to vector (SingleProbe) takes one chunk.
template <class Arch, class Fma, class Tally, class Search, class SearchVectors, class SearchTail>
void simd_resolve_in_chunks(const Frame& f, int y, const RowScratch& scratch, const Search& search, int chunk,
                            const SearchVectors& search_vectors, const SearchTail& search_tail) {
  constexpr int L = Lanes<Arch>::size;
  const RowContext<Arch> row(f, y, scratch);
  const int whole = f.target_width / L * L;
  Tally tally{};
  tally.row_path(static_cast<int>(row.path));
  with_color_path<Arch>(row.path, [&](auto path) {
    for (int begin = 0; begin < whole; begin += chunk) {
      const int end = std::min(begin + chunk, whole);
      search_vectors(begin, end);
      resolve_hits_of_path<decltype(path)::value, Arch, Fma>(row, begin, end, tally, search);
    }
  });
  tally.end_row();
  search_tail(whole, f.target_width);
  resolve_pixels<Fma>(f, y, scratch, whole, f.target_width);  // the tail
}

// Row y's resolve once its search has run (the tail's too), or as it runs (`search`). Scalar
// twin: resolve_pixels.
template <class Arch, class Fma, class Tally, class Search>
void simd_resolve_with(const Frame& f, int y, const RowScratch& scratch, const Search& search) {
  constexpr int L = Lanes<Arch>::size;
  const auto nothing = [](int, int) {};
  simd_resolve_in_chunks<Arch, Fma, Tally>(f, y, scratch, search, std::max(L, f.target_width / L * L), nothing, nothing);
}

template <class Arch, class Fma, class Tally = NoFetchTally>
void simd_resolve(const Frame& f, int y, const RowScratch& scratch) {
  simd_resolve_with<Arch, Fma, Tally>(f, y, scratch, StoredSearch<Arch>{scratch.source_x.data(), scratch.clipped.data()});
}

}  // namespace
}  // namespace reproject::detail
