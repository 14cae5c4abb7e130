// SIMD twin of kernels/march16.cpp (`march16`).
#pragma once

#include <algorithm>
#include <limits>
#include <type_traits>
#include <utility>

#include "kernels/resolve_simd.hpp"
#include "kernels/search_simd.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Scalar twin: search_row_march16.
// The samples' offsets and parallaxes are the same for every pixel, so they are tabled once per
// row. Only the row's deciding samples run (MarchRange), backwards and branch-free (the last
// select is the first hit, as in the scalar early exit). One to kSamplesInRegisters of them
// (every row of the default 16 steps that has any) run as one unrolled sequence whose rays and
// rows stay in registers across the row's vectors; more run in chunks, with an early exit between
// chunks once every lane has hit.

constexpr int kSamplesInRegisters = 17;  // the default Options::march_steps, 16, and its far end
constexpr int kMarchChunk = 16;
constexpr int kMarchGroup = 4;  // a chunk runs a whole number of groups of samples: unrolled
constexpr int kMaxMarchSamples = 1025;  // Options::march_steps <= 1024

// The samples [first, end) that decide the row's lanes; the others leave every lane as it is
// (DESIGN §6's march16 unchanged, only fewer reads). No surface of the row is on or behind a
// sample nearer than all of them, so none can be a lane's first hit; and every surface is on or
// behind a sample at or beyond the row's farthest one, so no lane looks past the first such
// sample. The row's surfaces are bounded by its columns [0, source_width): the padding repeats
// the edge columns. Samples may run past `end` (up to a whole group; beyond the last sample the
// table repeats it): a sample after one every lane hits changes nothing.
struct MarchRange {
  int first;
  int end;
};

template <class Arch>
MarchRange march_range(const Frame& f, const RowScratch& scratch, const float* sample_parallax, int samples) {
  REPROJECT_LANE_TYPES(Arch);
  const float* parallax = scratch.parallax;
  float lowest = parallax[0], highest = parallax[0];  // decoded parallax is never NaN
  int j = 0;
  if (f.source_width >= 4 * L) {
    // Four vectors a step, each with its own bounds: four times shorter chains of min and max.
    F low[4], high[4];
    for (int v = 0; v < 4; ++v) low[v] = high[v] = F::load_unaligned(parallax + v * L);
    for (; j + 4 * L <= f.source_width; j += 4 * L) {
      for (int v = 0; v < 4; ++v) {
        const F p = F::load_unaligned(parallax + j + v * L);
        low[v] = vmin(low[v], p);
        high[v] = vmax(high[v], p);
      }
    }
    lowest = lane_min<Arch>(vmin(vmin(low[0], low[1]), vmin(low[2], low[3])));
    highest = lane_max<Arch>(vmax(vmax(high[0], high[1]), vmax(high[2], high[3])));
  }
  for (; j < f.source_width; ++j) {
    lowest = std::min(lowest, parallax[j]);
    highest = std::max(highest, parallax[j]);
  }
  // Keys s * p (s is +-1: exact): a surface is on or behind a sample when its key is at least
  // the sample's.
  const float key_nearest = f.s > 0.0f ? highest : -lowest;
  const float key_farthest = f.s > 0.0f ? lowest : -highest;
  int first = 0;
  while (first < samples && !(key_nearest >= f.s * sample_parallax[first])) ++first;
  int end = first;
  while (end < samples && !(key_farthest >= f.s * sample_parallax[end])) ++end;
  return {first, std::min(end + 1, samples)};
}

// The march's two tests of a lane, on keys s * p with s = +-1 (Positive: s = +1) but without the
// multiplies by s (exact anyway, and a negation is exact): a surface on or behind a ray's sample,
// s * surface >= s * ray; and clipped, s * p > key_near, i.e. p > key_near or p < -key_near.
template <class Arch, bool Positive>
struct MarchTests {
  using F = typename Lanes<Arch>::F;
  using B = typename Lanes<Arch>::B;
  F clip_limit;
  explicit MarchTests(const Frame& f) : clip_limit(Positive ? f.key_near : -f.key_near) {}
  static B on_or_behind(const F& surface, const F& ray) { return Positive ? surface >= ray : surface <= ray; }
  B clipped(const F& p) const { return Positive ? p > clip_limit : p < clip_limit; }
};

// The vectors of target pixels [t_begin, t_end) of a row whose deciding samples are
// [first, first + sizeof...(K)), at most kSamplesInRegisters: every lane's first hit among them,
// or p_far, as the chunks of simd_march16_vectors compute, the samples' rays and rows held in
// registers across the vectors (the chunks read them from the tables at each vector: the stores
// may alias them). The selects start from p_far instead of NaN: the same value, no sample is NaN.
template <class Arch, bool Positive, int... K>
void simd_march16_in_registers(const Frame& f, RowScratch& scratch, const int* sample_offset,
                               const float* sample_parallax, int first, int t_begin, int t_end,
                               std::integer_sequence<int, K...>) {
  REPROJECT_LANE_TYPES(Arch);
  constexpr int kCount = sizeof...(K);
  const float* row0 = scratch.parallax + f.guard;  // lane t's samples: row0 + t + sample_offset[k]
  float* source_x = scratch.source_x.data();
  float* clipped = scratch.clipped.data();
  const MarchTests<Arch, Positive> tests(f);
  const F p_far(f.p_far), step(static_cast<float>(L));
  const float* const nearest_row = row0 + sample_offset[0];
  const float* const sample_row[kCount] = {row0 + sample_offset[first + K]...};
  const F ray[kCount] = {F(sample_parallax[first + K])...};
  F target = F(static_cast<float>(f.guard + t_begin)) + lane_offsets<Arch>();  // t + guard: exact small integers
  for (int t = t_begin; t < t_end; t += L) {
    store_flags<Arch>(tests.clipped(F::load_unaligned(nearest_row + t)), clipped + t);
    F hit = p_far;
    auto sample = [&](int k) {
      const F surface = F::load_unaligned(sample_row[k] + t);
      hit = xsimd::select(tests.on_or_behind(surface, ray[k]), surface, hit);
    };
    (sample(kCount - 1 - K), ...);  // backwards
    (target - hit).store_unaligned(source_x + t);
    target = target + step;
  }
}

// Calls march(std::make_integer_sequence<int, count>{}): one unrolled body per count. The caller
// keeps count in [N, kSamplesInRegisters] (a count above it would run the last body).
template <int N = 1, class March>
void with_sample_count(int count, const March& march) {
  if constexpr (N < kSamplesInRegisters) {
    if (count != N) return with_sample_count<N + 1>(count, march);
  }
  march(std::make_integer_sequence<int, N>{});
}

// The vectors of target pixels [t_begin, t_end) (whole vectors: t_begin and t_end multiples of
// L), the row's samples tabled and its range found (MarchRow).
template <class Arch, class Fma, bool Positive>
void simd_march16_vectors(const Frame& f, RowScratch& scratch, const int* sample_offset, const float* sample_parallax,
                          MarchRange range, int t_begin, int t_end) {
  const int deciding = range.end - range.first;
  if (deciding >= 1 && deciding <= kSamplesInRegisters) {
    return with_sample_count(deciding, [&](auto samples) {
      simd_march16_in_registers<Arch, Positive>(f, scratch, sample_offset, sample_parallax, range.first, t_begin, t_end,
                                                samples);
    });
  }
  REPROJECT_LANE_TYPES(Arch);
  // Locals, not f's or scratch's fields: the stores below go through float pointers, which may
  // alias them, so fields would be reloaded after each store.
  const float* row0 = scratch.parallax + f.guard;  // lane t's samples: row0 + t + sample_offset[k]
  float* source_x = scratch.source_x.data();
  float* clipped = scratch.clipped.data();
  const MarchTests<Arch, Positive> tests(f);
  const F p_far(f.p_far), step(static_cast<float>(L));
  const F nan(std::numeric_limits<float>::quiet_NaN());
  // The parallax of the first of samples [first, first + count) on or behind the surface, NaN if
  // none (decoded parallax is never NaN): backwards and branch-free, so the last select is the
  // first hit, as in the scalar early exit. count is constant: unrolled.
  auto chunk = [&](const float* row, int first, auto count) {
    const int* offset = sample_offset + first;
    const float* ray = sample_parallax + first;
    F hit = nan;
    for (int k = count - 1; k >= 0; --k) {
      // The k-th sample of every lane is at the same offset: one contiguous load.
      const F surface = F::load_unaligned(row + offset[k]);
      hit = xsimd::select(tests.on_or_behind(surface, F(ray[k])), surface, hit);
    }
    return hit;
  };
  // A chunk of `groups` groups (1 to kMarchChunk / kMarchGroup), the same for every vector of
  // the row but the last chunk's: a well-predicted branch to an unrolled chunk.
  auto chunk_of_groups = [&](const float* row, int first, int groups) {
    using std::integral_constant;
    switch (groups) {
      case 1: return chunk(row, first, integral_constant<int, kMarchGroup>{});
      case 2: return chunk(row, first, integral_constant<int, 2 * kMarchGroup>{});
      case 3: return chunk(row, first, integral_constant<int, 3 * kMarchGroup>{});
      default: return chunk(row, first, integral_constant<int, kMarchChunk>{});
    }
  };
  static_assert(kMarchChunk == 4 * kMarchGroup, "chunk_of_groups' cases");
  F target = F(static_cast<float>(f.guard + t_begin)) + lane_offsets<Arch>();  // t + guard: exact small integers
  for (int t = t_begin; t < t_end; t += L) {
    const float* row = row0 + t;
    store_flags<Arch>(tests.clipped(F::load_unaligned(row + sample_offset[0])), clipped + t);
    // The parallax of the first sample on or behind the surface; no hit: the far end.
    F hit_parallax = p_far;
    B done(false);
    for (int first = range.first; first < range.end; first += kMarchChunk) {
      const int groups = (std::min(range.end - first, kMarchChunk) + kMarchGroup - 1) / kMarchGroup;
      const F chunk_parallax = chunk_of_groups(row, first, groups);
      const B chunk_hit = chunk_parallax == chunk_parallax;
      hit_parallax = xsimd::select(chunk_hit & ~done, chunk_parallax, hit_parallax);
      done = done | chunk_hit;
      if (xsimd::all(done)) break;
    }
    (target - hit_parallax).store_unaligned(source_x + t);
    target = target + step;
  }
}

// One row's march: its samples tabled and its range found once, then any whole vectors of it.
template <class Arch, class Fma>
class MarchRow {
 public:
  MarchRow(const Frame& f, RowScratch& scratch) : f_(f), scratch_(scratch) {
    const int samples = f.march_steps + 1;
    // A whole group past the last sample: the last sample again (march_range).
    for (int k = 0; k < samples + kMarchGroup; ++k) {
      sample_parallax_[k] = madd<Fma>(static_cast<float>(std::min(k, samples - 1)), f.march_step, f.p_near);
      sample_offset_[k] = point_offset(sample_parallax_[k]);
    }
    range_ = march_range<Arch>(f, scratch, sample_parallax_, samples);
  }
  // Target pixels [t_begin, t_end), multiples of the vector length.
  void vectors(int t_begin, int t_end) const {
    if (f_.s > 0.0f) simd_march16_vectors<Arch, Fma, true>(f_, scratch_, sample_offset_, sample_parallax_, range_, t_begin, t_end);
    else simd_march16_vectors<Arch, Fma, false>(f_, scratch_, sample_offset_, sample_parallax_, range_, t_begin, t_end);
  }

 private:
  const Frame& f_;
  RowScratch& scratch_;
  int sample_offset_[kMaxMarchSamples + kMarchGroup];
  float sample_parallax_[kMaxMarchSamples + kMarchGroup];
  MarchRange range_;
};

template <class Arch, class Fma>
void simd_march16(const Frame& f, RowScratch& scratch) {
  constexpr int L = Lanes<Arch>::size;
  const int whole = f.target_width / L * L;
  MarchRow<Arch, Fma>(f, scratch).vectors(0, whole);
  search_row_march16<Fma>(f, scratch, whole, f.target_width);
}

// `march16`'s search and the resolve in chunks of kMarchResolveChunk target pixels
// (KernelTable::march16_and_resolve): each chunk's x and clipped rows are read back by its
// resolve while still in L1, where a whole row's may not be (at 4K a row's x, clipped, parallax,
// source and output rows are about 75 KB). The same bits as simd_march16 then simd_resolve.
constexpr int kMarchResolveChunk = 1024;  // a multiple of every set's vector length

template <class Arch, class Fma, class Tally = NoFetchTally>
void simd_march16_and_resolve(const Frame& f, int y, RowScratch& scratch) {
  static_assert(kMarchResolveChunk % Lanes<Arch>::size == 0, "chunks of whole vectors");
  const MarchRow<Arch, Fma> march(f, scratch);
  simd_resolve_in_chunks<Arch, Fma, Tally>(
      f, y, scratch, StoredSearch<Arch>{scratch.source_x.data(), scratch.clipped.data()}, kMarchResolveChunk,
      [&](int t_begin, int t_end) { march.vectors(t_begin, t_end); },
      [&](int t_begin, int t_end) { search_row_march16<Fma>(f, scratch, t_begin, t_end); });
}

}  // namespace
}  // namespace reproject::detail
