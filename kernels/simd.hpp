// Internal: the SIMD primitives every twin shares, written once with xsimd over the arch layer
// (kernels/arch_layer.hpp: the contracts of FMA per width, floor/min/max, gathers, permutes, lane
// reductions, byte, 16-bit and half stores; one family file per processor defines them).
// Instantiated per instruction set by kernels/arch_<set>.cpp, each compiled with its own flags
// (kernels/simd_table.hpp assembles a table). Lanes are consecutive target pixels.
//
// Each twin mirrors its scalar reference operation for operation (same FMA policy, same
// divisions, no approximate reciprocals), so the outputs are bit-identical; tails shorter than
// a vector run the scalar reference itself (docs/DESIGN.md §8).
#pragma once

#include <cstdint>
#include <type_traits>
#include <xsimd/xsimd.hpp>

#include "kernels/arch_layer.hpp"
#include "kernels/kernel_table.hpp"

namespace reproject::detail {
namespace {  // one copy per arch TU (kernels/fma.hpp)

// Negation of lane masks is written ~mask: xsimd 8.1's !mask compares with `false`, which on AVX
// goes through two 128-bit integer compares; ~ is one xor (and folds into andnot).
template <class Arch>
struct Lanes {
  static_assert(has_arch_block<Arch>(), "the arch layer serves this instruction set");
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using B = xsimd::batch_bool<float, Arch>;
  static constexpr int size = static_cast<int>(F::size);
};

// A twin's vector types, in one line: F (float lanes), I (int32 lanes), B (float lane masks) and
// L (how many lanes), for the instruction set Arch.
#define REPROJECT_LANE_TYPES(Arch)                               \
  using F [[maybe_unused]] = typename Lanes<Arch>::F;           \
  using I [[maybe_unused]] = typename Lanes<Arch>::I;           \
  using B [[maybe_unused]] = typename Lanes<Arch>::B;           \
  [[maybe_unused]] constexpr int L = Lanes<Arch>::size

template <class Arch>
xsimd::batch<float, Arch> lane_offsets() {
  alignas(64) static const float offsets[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  return xsimd::batch<float, Arch>::load_aligned(offsets);
}

template <class Arch>
float lane_min(const xsimd::batch<float, Arch>& v) {
  return lane_extreme<Arch, false>(v);
}
template <class Arch>
float lane_max(const xsimd::batch<float, Arch>& v) {
  return lane_extreme<Arch, true>(v);
}

// Flags (clipped per target pixel) as floats 1 or 0, so that a vector reads them with one load.
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

// The resolve stage's data-dependent reads (docs/DESIGN.md §6, "SIMD"). On smooth surfaces a
// vector's source columns are nearly consecutive, so contiguous loads and permutes replace the
// gathers, which are much slower. The same two column sets are read from every plane of the row,
// so the plan is made once per vector and the lane indices once per column set.
// Modes, on every width with a permute (has_permute; otherwise it gathers):
//  * `consecutive`: first[i] = base + i and second[i] = base + i + 1 (a surface at constant
//    parallax): two plain loads;
//  * `shifted`: first[i] within L columns from `base`, and second[i] within L columns from
//    base + 1 (second = first + 1 except at the row end and in hole fills): two loads, one
//    permute each;
//  * `spanning`: both sets within 2L columns from `base`: two loads and a two-register permute
//    per set;
//  * otherwise gathers.
// Vectors per column-fetch mode: the resolve tells its tally the mode of every vector it fetches,
// and each row's colour path (kernels/resolve_row_simd.hpp ColorPath). The library's tables count
// nothing (NoFetchTally: empty, so the calls compile to nothing and the release loops carry no
// counter); the tests build tables of their own with a counting tally (tests/arch_layer/set.cpp)
// to show that every mode ran, and that a frame took the colour path it was planned for.
struct NoFetchTally {
  void add(int /*mode*/) {}
  void row_path(int /*color_path*/) {}
  void end_row() {}
};

template <class Arch>
class ColumnFetch {
 public:
  using F = typename Lanes<Arch>::F;
  using I = typename Lanes<Arch>::I;
  static constexpr int L = Lanes<Arch>::size;

  // Columns first[i] and second[i] (first <= second) will be read from rows that hold at
  // least `row_length` columns; every load stays inside them.
  explicit ColumnFetch(int row_length) : row_length_(row_length) {}
  ColumnFetch(const F& first, const F& second, int row_length) : row_length_(row_length) { bind(first, second); }

  // The order of a tally's modes.
  enum class Mode { consecutive, shifted, spanning, gather };
  Mode mode() const { return mode_; }

  // (Re)plans for new column sets (hole fills).
  void bind(const F& first, const F& second) {
    plan<false>(first, [&] { return second; }, [&](auto mode) REPROJECT_ALWAYS_INLINE { mode_ = decltype(mode)::value; });
  }

  // Plans for first and second = min(first + 1, last_column) (the hit loop's columns), then
  // returns body(fetch) with a fetch compiled for the plan: one branch per vector, on the plan
  // itself, instead of a plan and then a switch on it. (second is computed only by the modes
  // that read it: not by the consecutive one, the common case.)
  template <class Body>
  REPROJECT_ALWAYS_INLINE bool plan_next_and_visit(const F& first, const F& last_column, const Body& body) {
    const auto second = [&]() REPROJECT_ALWAYS_INLINE { return vmin(first + F(1.0f), last_column); };
    return plan<true>(first, second, [&](auto mode) REPROJECT_ALWAYS_INLINE {
      mode_ = decltype(mode)::value;
      return body(Fetch<decltype(mode)::value>{this});
    });
  }

  // A row's values at both column sets.
  void fetch(const float* row, F& at_first, F& at_second) const {
    visit([&](const auto& fetch_as) { fetch_as(row, at_first, at_second); });
  }

  // Calls body(fetch) with a fetch(row, at_first, at_second) compiled for this vector's mode, so
  // that a body reading several rows branches on the mode once, not once per row.
  template <class Body>
  REPROJECT_ALWAYS_INLINE void visit(const Body& body) const {
    switch (mode_) {
      case Mode::consecutive: return body(Fetch<Mode::consecutive>{this});
      case Mode::shifted: return body(Fetch<Mode::shifted>{this});
      case Mode::spanning: return body(Fetch<Mode::spanning>{this});
      case Mode::gather: break;
    }
    body(Fetch<Mode::gather>{this});
  }

 private:
  template <Mode M>
  using ModeTag = std::integral_constant<Mode, M>;

  // Sets the lane indices of the plan for first and second = second_of() and returns
  // on(ModeTag). SecondIsNext: the caller promises second = min(first + 1, last column) (so a
  // consecutive first, whose columns end before the row does, has a consecutive second).
  template <bool SecondIsNext, class SecondOf, class OnMode>
  REPROJECT_ALWAYS_INLINE auto plan(const F& first, const SecondOf& second_of, const OnMode& on) {
    if constexpr (has_permute<Arch>()) {
      // Lane i reads column base + i (and base + i + 1): plain loads, nothing to permute. Tested
      // from lane 0 first, without a reduction: the common case on smooth surfaces.
      const float lane0 = first_lane<Arch>(first);
      const F lanes = F(lane0) + lane_offsets<Arch>();
      base_ = static_cast<int>(lane0);
      if (base_ + L < row_length_ &&
          xsimd::all(SecondIsNext ? first == lanes : (first == lanes) & (second_of() == lanes + F(1.0f)))) {
        return on(ModeTag<Mode::consecutive>{});
      }
      const F second = second_of();
      // Lane 0 holds the lowest column on most surfaces (x grows with t): then no reduction. The
      // same plan as from lane_min: with no NaN, the two differ at most in a zero's sign, which the
      // plan does not see.
      const float lowest = xsimd::all(first >= F(lane0)) ? lane0 : lane_min<Arch>(first);
      switch (plan_permutes(first, second, lowest)) {
        case Mode::shifted: return on(ModeTag<Mode::shifted>{});
        case Mode::spanning: return on(ModeTag<Mode::spanning>{});
        default: break;
      }
      return plan_gather(first, second, on);
    } else {
      return plan_gather(first, second_of(), on);
    }
  }

  // The permute mode for columns at or above `lowest` (a lane's value), with base_ and the lane
  // indices set for it; Mode::gather, with no indices set, if neither fits (the caller then plans
  // the gather).
  REPROJECT_ALWAYS_INLINE Mode plan_permutes(const F& first, const F& second, float lowest) {
    base_ = static_cast<int>(lowest);
    const F from_base = first - F(lowest);
    const F second_from_base = second - F(lowest);
    if (base_ + L < row_length_ &&
        xsimd::all((from_base < F(static_cast<float>(L))) & (second_from_base >= F(1.0f)) &
                   (second_from_base <= F(static_cast<float>(L))))) {
      index_for_permute(first_, xsimd::to_int(from_base));
      index_for_permute(second_, xsimd::to_int(second_from_base - F(1.0f)));
      return Mode::shifted;
    }
    if (base_ + 2 * L <= row_length_ && xsimd::all(second_from_base < F(static_cast<float>(2 * L)))) {
      index_for_two_registers(first_, xsimd::to_int(from_base));
      index_for_two_registers(second_, xsimd::to_int(second_from_base));
      return Mode::spanning;
    }
    return Mode::gather;
  }

  template <class OnMode>
  REPROJECT_ALWAYS_INLINE auto plan_gather(const F& first, const F& second, const OnMode& on) {
    index_for_gather(first_, xsimd::to_int(first));
    index_for_gather(second_, xsimd::to_int(second));
    return on(ModeTag<Mode::gather>{});
  }

 public:
  // A fetch compiled for one mode: fetch(row, at_first, at_second).
  template <Mode M>
  struct Fetch {
    static constexpr Mode mode = M;
    const ColumnFetch* columns;
    void operator()(const float* row, F& at_first, F& at_second) const { columns->fetch_as<M>(row, at_first, at_second); }
  };

 private:
  template <Mode M>
  void fetch_as(const float* row, F& at_first, F& at_second) const {
    if constexpr (has_permute<Arch>()) {
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
        at_first = permute_two_registers<Arch>(low, high, first_);
        at_second = permute_two_registers<Arch>(low, high, second_);
        return;
      }
    }
    at_first = gather<Arch>(row, first_.index);
    at_second = gather<Arch>(row, second_.index);
  }

  Mode mode_ = Mode::gather;
  int row_length_;
  int base_ = 0;
  // Each column set's lanes (the arch layer's LaneIndex): absolute for gathers, from `base` for
  // the permutes. Set by plan() for the modes that read them, and not zeroed by it (a vector's
  // worth of stores per plan, in the resolve's hottest loop); zeroed once when constructed (once
  // per row, or per resolve_vector call), which also keeps GCC's -Wmaybe-uninitialized quiet: with
  // resolve_vector inlined per colour path, g++ 12 with xsimd 13.2 could not see that a mode's
  // fetch reads only what its plan set.
  LaneIndex<Arch> first_{}, second_{};
};

}  // namespace
}  // namespace reproject::detail
