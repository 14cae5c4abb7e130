// Shared SIMD primitives of the kernels' twins (kernels/<method>_simd.hpp, kernels/stages_simd.hpp),
// written once with xsimd and instantiated per instruction set by kernels/arch_<set>.cpp (each
// compiled with its own flags; kernels/simd_table.hpp assembles a table). Lanes are consecutive
// target pixels. Everything here is in an anonymous namespace: each arch TU gets its own copy, so
// the linker can never pick an AVX-512 body for an SSE caller (ODR).
//
// Each twin mirrors its scalar reference operation for operation (same FMA policy, same
// divisions, no approximate reciprocals), so the outputs are bit-identical; tails shorter than
// a vector run the scalar reference itself. Intrinsics appear only where xsimd 8.1 has no fast or
// no exact form (FMA on AVX-512, gathers, permutes, lane reductions, byte stores): each such
// branch is here, beside its twins for the other widths.
#pragma once

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <xsimd/xsimd.hpp>

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {
namespace {  // one copy per arch TU (kernels/simd.hpp)

// Negation of lane masks is written ~mask: xsimd 8.1's !mask compares with `false`, which on AVX
// goes through two 128-bit integer compares; ~ is one xor (and folds into andnot).
template <class Arch>
struct Lanes {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using B = xsimd::batch_bool<float, Arch>;
  static constexpr int size = static_cast<int>(F::size);
};

// The FMA policy of frame.hpp, on vectors. The fused form names the instruction for each width
// instead of calling xsimd::fma: xsimd 8.1 has no fma kernel for avx512f, and there xsimd::fma
// falls back to the generic x * y + z (two roundings under -ffp-contract=off), which silently broke
// bit-identity on AVX-512. A width without an FMA instruction in this TU does not compile.
// tests/check_object_code.cmake holds every fused object to vector FMAs of its width.
template <class Fma, class F>
F vmadd(const F& a, const F& b, const F& c) {
  if constexpr (!std::is_same<Fma, Fused>::value) {
    return a * b + c;
#if defined(__AVX512F__)
  } else if constexpr (sizeof(F) == 64) {
    return _mm512_fmadd_ps(a, b, c);
#endif
#if defined(__FMA__)
  } else if constexpr (sizeof(F) == 32) {
    return _mm256_fmadd_ps(a, b, c);
  } else if constexpr (sizeof(F) == 16) {
    return _mm_fmadd_ps(a, b, c);
#endif
  } else {
    static_assert(!std::is_same<F, F>::value, "the fused policy needs an FMA instruction of this width");
  }
}

template <class Arch>
xsimd::batch<float, Arch> lane_offsets() {
  alignas(64) static const float offsets[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  return xsimd::batch<float, Arch>::load_aligned(offsets);
}

// base[index] per lane. xsimd 8.1's batch::gather is a scalar loop, so use the hardware gather
// where there is one.
template <class Arch>
xsimd::batch<float, Arch> gather(const float* base, const xsimd::batch<std::int32_t, Arch>& index) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of<xsimd::avx512f, Arch>::value) {
    return _mm512_i32gather_ps(index, base, 4);
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of<xsimd::avx2, Arch>::value) {
    return _mm256_i32gather_ps(base, index, 4);
  }
#endif
  constexpr int L = Lanes<Arch>::size;
  alignas(64) std::int32_t at[L];
  alignas(64) float value[L];
  index.store_aligned(at);
  // memcpy: `base` may be a row of 32-bit pixels (rgba8) at any byte address.
  for (int i = 0; i < L; ++i) std::memcpy(&value[i], base + at[i], sizeof(float));
  return xsimd::batch<float, Arch>::load_aligned(value);
}

// Indices are carried as exact small floats (selects stay in one domain) and converted here.
template <class Arch>
xsimd::batch<float, Arch> gather_at(const float* base, const xsimd::batch<float, Arch>& index) {
  return gather<Arch>(base, xsimd::to_int(index));
}

// Horizontal minimum (Max false) or maximum (Max true) of a vector, with the min/max instructions
// themselves. (The maximum is not written -lane_min(-v): xsimd 8.1's avx512f negation is 0 - x,
// which turns a +0 lane into +0 instead of -0. Which zero a reduction of +0 and -0 returns depends
// on the order; set_near_key makes the frame's nearest key +0 in that case.)
template <class Arch, bool Max>
float lane_extreme(const xsimd::batch<float, Arch>& v) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of<xsimd::avx512f, Arch>::value) return Max ? _mm512_reduce_max_ps(v) : _mm512_reduce_min_ps(v);
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of<xsimd::avx2, Arch>::value) {
    auto op = [](__m256 x, __m256 y) { return Max ? _mm256_max_ps(x, y) : _mm256_min_ps(x, y); };
    __m256 m = op(v, _mm256_permute2f128_ps(v, v, 1));
    m = op(m, _mm256_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
    m = op(m, _mm256_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm256_cvtss_f32(m);
  }
#endif
  constexpr int L = Lanes<Arch>::size;
  alignas(64) float lanes[L];
  v.store_aligned(lanes);
  return Max ? *std::max_element(lanes, lanes + L) : *std::min_element(lanes, lanes + L);
}
template <class Arch>
float lane_min(const xsimd::batch<float, Arch>& v) {
  return lane_extreme<Arch, false>(v);
}
template <class Arch>
float lane_max(const xsimd::batch<float, Arch>& v) {
  return lane_extreme<Arch, true>(v);
}

// Lane 0 of a vector, and a one-register permute (lane i takes v[index[i]]), for the widths that
// have a variable permute instruction (AVX2: 8 lanes, AVX-512: 16).
template <class Arch>
constexpr bool kHasPermute =
#if defined(__AVX512F__)
    std::is_base_of<xsimd::avx512f, Arch>::value ||
#endif
#if defined(__AVX2__)
    std::is_base_of<xsimd::avx2, Arch>::value ||
#endif
    false;

template <class Arch>
float first_lane(const xsimd::batch<float, Arch>& v) {
  static_assert(kHasPermute<Arch>, "first_lane() serves the AVX2 and AVX-512 fetch plans");
#if defined(__AVX512F__)
  if constexpr (sizeof(v) == 64) {
    return _mm512_cvtss_f32(v);
  } else
#endif
  {
    return _mm256_cvtss_f32(v);
  }
}

template <class Arch>
xsimd::batch<float, Arch> permute([[maybe_unused]] const xsimd::batch<float, Arch>& v,
                                  [[maybe_unused]] const xsimd::batch<std::int32_t, Arch>& index) {
  static_assert(kHasPermute<Arch>, "permute() needs AVX2 or AVX-512");
#if defined(__AVX512F__)
  if constexpr (sizeof(v) == 64) return _mm512_permutexvar_ps(index, v);
#endif
#if defined(__AVX2__)
  if constexpr (sizeof(v) == 32) return _mm256_permutevar8x32_ps(v, index);
#endif
}

// The resolve stage's data-dependent reads (DESIGN §6 SIMD hints). On smooth surfaces a vector's
// source columns are nearly consecutive, so contiguous loads and permutes replace the gathers,
// which are much slower (on AVX2 and AVX-512). The same two column sets are read from every plane
// of the row, so the plan is made once per vector and the lane indices once per column set.
// Modes, on AVX2 and AVX-512 alike (SSE has no variable permute: it gathers):
//  * `consecutive`: first[i] = base + i and second[i] = base + i + 1 (a surface at constant
//    parallax): two plain loads;
//  * `shifted`: first[i] within L columns from `base`, and second[i] within L columns from
//    base + 1 (second = first + 1 except at the row end and in hole fills): two loads, one
//    permute each;
//  * `spanning`: both sets within 2L columns from `base`: two loads and a two-register permute
//    per set (one instruction on AVX-512; on AVX2 two permutes and a blend);
//  * otherwise hardware gathers.
// The calling thread's FetchModeCounts of this table (this TU's copy: the namespace is anonymous).
// initial-exec: one fs-relative add per vector, not a __tls_get_addr call.
__attribute__((tls_model("initial-exec"))) inline thread_local FetchModeCounts t_fetch_modes{};
inline FetchModeCounts* fetch_modes_of_thread() { return &t_fetch_modes; }

template <class Arch>
class ColumnFetch {
 public:
  using F = typename Lanes<Arch>::F;
  using I = typename Lanes<Arch>::I;
  static constexpr int L = Lanes<Arch>::size;
#if defined(__AVX512F__)
  static constexpr bool kAvx512 = std::is_base_of<xsimd::avx512f, Arch>::value;
#else
  static constexpr bool kAvx512 = false;
#endif
#if defined(__AVX2__)
  static constexpr bool kAvx2 = std::is_base_of<xsimd::avx2, Arch>::value;
#else
  static constexpr bool kAvx2 = false;
#endif

  // Columns first[i] and second[i] (first <= second) will be read from rows that hold at
  // least `row_length` columns; every load stays inside them.
  ColumnFetch(const F& first, const F& second, int row_length) : row_length_(row_length), first_(0), second_(0) {
    bind(first, second);
  }

  // (Re)plans for new column sets (hole fills).
  void bind(const F& first, const F& second) {
    mode_ = plan(first, second);
    ++t_fetch_modes.vectors[static_cast<int>(mode_)];
  }

  // The order of FetchModeCounts.
  enum class Mode { consecutive, shifted, spanning, gather };
  Mode mode() const { return mode_; }

  // A row's values at both column sets.
  void fetch(const float* row, F& at_first, F& at_second) const {
    visit([&](const auto& fetch_as) { fetch_as(row, at_first, at_second); });
  }

  // Calls body(fetch) with a fetch(row, at_first, at_second) compiled for this vector's mode, so
  // that a body reading several rows branches on the mode once, not once per row.
  template <class Body>
  void visit(const Body& body) const {
    switch (mode_) {
      case Mode::consecutive: return body(Fetch<Mode::consecutive>{this});
      case Mode::shifted: return body(Fetch<Mode::shifted>{this});
      case Mode::spanning: return body(Fetch<Mode::spanning>{this});
      case Mode::gather: break;
    }
    body(Fetch<Mode::gather>{this});
  }

 private:
  Mode plan(const F& first, const F& second) {
    if constexpr (kHasPermute<Arch>) {
      // Lane i reads column base + i (and base + i + 1): plain loads, nothing to permute. Tested
      // from lane 0 first, without a reduction: the common case on smooth surfaces.
      const float lane0 = first_lane<Arch>(first);
      const F lanes = F(lane0) + lane_offsets<Arch>();
      base_ = static_cast<int>(lane0);
      if (base_ + L < row_length_ && xsimd::all((first == lanes) & (second == lanes + F(1.0f)))) {
        return Mode::consecutive;
      }
      const float lowest = lane_min<Arch>(first);
      base_ = static_cast<int>(lowest);
      const F from_base = first - F(lowest);
      const F second_from_base = second - F(lowest);
      if (base_ + L < row_length_ &&
          xsimd::all((from_base < F(static_cast<float>(L))) & (second_from_base >= F(1.0f)) &
                     (second_from_base <= F(static_cast<float>(L))))) {
        first_ = xsimd::to_int(from_base);
        second_ = xsimd::to_int(second_from_base - F(1.0f));
        return Mode::shifted;
      }
      if (base_ + 2 * L <= row_length_ && xsimd::all(second_from_base < F(static_cast<float>(2 * L)))) {
        first_ = xsimd::to_int(from_base);
        second_ = xsimd::to_int(second_from_base);
#if defined(__AVX2__)
        if constexpr (kAvx2) {
          first_high_ = _mm256_castsi256_ps(_mm256_cmpgt_epi32(first_, _mm256_set1_epi32(L - 1)));
          second_high_ = _mm256_castsi256_ps(_mm256_cmpgt_epi32(second_, _mm256_set1_epi32(L - 1)));
        }
#endif
        return Mode::spanning;
      }
    }
    first_ = xsimd::to_int(first);
    second_ = xsimd::to_int(second);
    return Mode::gather;
  }


  template <Mode M>
  struct Fetch {
    const ColumnFetch* columns;
    void operator()(const float* row, F& at_first, F& at_second) const { columns->fetch_as<M>(row, at_first, at_second); }
  };

  template <Mode M>
  void fetch_as(const float* row, F& at_first, F& at_second) const {
    if constexpr (kHasPermute<Arch>) {
      if constexpr (M == Mode::consecutive) {
        at_first = F::load_unaligned(row + base_);
        at_second = F::load_unaligned(row + base_ + 1);
        return;
      }
      if constexpr (M == Mode::shifted) {
        at_first = permute<Arch>(F::load_unaligned(row + base_), first_);
        at_second = permute<Arch>(F::load_unaligned(row + base_ + 1), second_);
        return;
      }
      if constexpr (M == Mode::spanning) {
        const F low = F::load_unaligned(row + base_);
        const F high = F::load_unaligned(row + base_ + L);
#if defined(__AVX512F__)
        if constexpr (kAvx512) {
          at_first = _mm512_permutex2var_ps(low, first_, high);
          at_second = _mm512_permutex2var_ps(low, second_, high);
          return;
        }
#endif
#if defined(__AVX2__)
        if constexpr (kAvx2) {
          // AVX2's permute reaches one register: permute both, then take each lane's own.
          at_first = _mm256_blendv_ps(permute<Arch>(low, first_), permute<Arch>(high, first_), first_high_);
          at_second = _mm256_blendv_ps(permute<Arch>(low, second_), permute<Arch>(high, second_), second_high_);
          return;
        }
#endif
      }
    }
    at_first = gather<Arch>(row, first_);
    at_second = gather<Arch>(row, second_);
  }

  Mode mode_ = Mode::gather;
  int row_length_;
  int base_ = 0;
  I first_, second_;
#if defined(__AVX2__)
  __m256 first_high_ = _mm256_setzero_ps();  // `spanning` on AVX2: lanes that come from the second load
  __m256 second_high_ = _mm256_setzero_ps();
#endif
};

// Stores the first `count` lanes of `value` (count >= 0; all of them when count >= L) and leaves
// the memory after them untouched: a hardware masked store on AVX2 and AVX-512.
template <class Arch>
void store_first_lanes(const xsimd::batch<float, Arch>& value, float* out, int count) {
  using F = typename Lanes<Arch>::F;
  constexpr int L = Lanes<Arch>::size;
  if (count >= L) return value.store_unaligned(out);
#if defined(__AVX512F__)
  if constexpr (sizeof(value) == 64) {
    return _mm512_mask_storeu_ps(out, static_cast<__mmask16>((1u << count) - 1u), value);
  }
#endif
#if defined(__AVX2__)
  if constexpr (sizeof(value) == 32) {
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    return _mm256_maskstore_ps(out, _mm256_cmpgt_epi32(_mm256_set1_epi32(count), lanes), value);
  }
#endif
  xsimd::select(lane_offsets<Arch>() < F(static_cast<float>(count)), value, F::load_unaligned(out)).store_unaligned(out);
}

template <class Arch>
void store_flags(const xsimd::batch_bool<float, Arch>& flags, float* out) {
  using F = typename Lanes<Arch>::F;
  xsimd::select(flags, F(1.0f), F(0.0f)).store_unaligned(out);
}

template <class Arch>
xsimd::batch_bool<float, Arch> load_flags(const float* in) {
  using F = typename Lanes<Arch>::F;
  return F::load_unaligned(in) != F(0.0f);
}

// Stores small non-negative integral floats (the PixelStatus values) as bytes.
template <class Arch>
void store_bytes(const xsimd::batch<float, Arch>& value, std::uint8_t* out) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of<xsimd::avx512f, Arch>::value) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm512_cvtusepi32_epi8(_mm512_cvttps_epi32(value)));
    return;
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of<xsimd::avx2, Arch>::value) {
    const __m256i words = _mm256_cvttps_epi32(value);
    const __m128i halves = _mm_packus_epi32(_mm256_castsi256_si128(words), _mm256_extracti128_si256(words, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out), _mm_packus_epi16(halves, halves));
    return;
  }
#endif
  constexpr int L = Lanes<Arch>::size;
  alignas(64) float lanes[L];
  value.store_aligned(lanes);
  for (int i = 0; i < L; ++i) out[i] = static_cast<std::uint8_t>(lanes[i]);
}

// Parallax at a lane-invariant offset from each lane's target column: two contiguous loads.
template <class Arch, class Fma>
xsimd::batch<float, Arch> parallax_at_offset_v(const float* parallax, int target0, float offset) {
  using F = typename Lanes<Arch>::F;
  const float whole = std::floor(offset);
  const float* p = parallax + target0 + static_cast<int>(whole);
  const F p0 = F::load_unaligned(p);
  const F p1 = F::load_unaligned(p + 1);
  return vmadd<Fma>(F(offset - whole), p1 - p0, p0);
}

template <class Arch, class Fma>
xsimd::batch<float, Arch> intersect_v(const xsimd::batch<float, Arch>& x_front, const xsimd::batch<float, Arch>& gap_front,
                                      const xsimd::batch<float, Arch>& x_behind, const xsimd::batch<float, Arch>& gap_behind) {
  const auto t = gap_front / (gap_front - gap_behind);
  return vmadd<Fma>(t, x_behind - x_front, x_front);
}

// ---- the column march of scanline and secant (scalar twin: march_columns) ----
// Lanes in `done` keep `offset`; the others get the offset of their first crossing.

template <class Arch, class Fma>
xsimd::batch<float, Arch> simd_march_columns(const Frame& f, const float* parallax, int target0, float o_start,
                                             xsimd::batch<float, Arch> gap_prev, xsimd::batch_bool<float, Arch> done,
                                             xsimd::batch<float, Arch> offset, float o_end) {
  using F = typename Lanes<Arch>::F;
  using B = typename Lanes<Arch>::B;
  const F s(f.s), zero(0.0f);
  const ColumnWalk walk = column_walk(f, o_start, o_end);
  float o_prev = o_start;
  for (int o = walk.first; walking(walk, o); o += walk.step) {
    const float column = static_cast<float>(o);
    const F gap = s * (F(-column) - F::load_unaligned(parallax + target0 + o));
    const B hit = (gap <= zero) & ~done;
    if (xsimd::any(hit)) {
      offset = xsimd::select(hit, intersect_v<Arch, Fma>(F(o_prev), gap_prev, F(column), gap), offset);
      done = done | hit;
      if (xsimd::all(done)) return offset;
    }
    o_prev = column;
    gap_prev = gap;
  }
  const F gap = s * (F(-o_end) - parallax_at_offset_v<Arch, Fma>(parallax, target0, o_end));
  const B hit = (gap <= zero) & ~done;
  offset = xsimd::select(hit, intersect_v<Arch, Fma>(F(o_prev), gap_prev, F(o_end), gap), offset);
  return xsimd::select(done | hit, offset, F(o_end));
}

}  // namespace
}  // namespace detail
}  // namespace reproject
