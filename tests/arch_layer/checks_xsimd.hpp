// The xsimd operations the twins call directly (kernels/arch_layer.hpp, "xsimd as the twins use
// it"): selects, comparisons, masks, conversions, integer and float arithmetic, each against the
// scalar statement the kernels rely on. Newer xsimd releases changed several of these (min/max,
// bitwise_cast, batch_bool conversions, select), so a change shows here by name, not as a frame.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "kernels/simd.hpp"
#include "tests/arch_layer/sets.hpp"
#include "tests/arch_layer/values.hpp"

namespace reproject::test {
namespace {

template <class Arch>
Outcome check_xsimd_select() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  int pattern = 0;
  every_tuple_in_every_lane<L, 2>(special_values(), [&](const std::uint32_t* a, const std::uint32_t* b) {
    bool take_a[L];
    ++pattern;
    for (int i = 0; i < L; ++i) take_a[i] = ((pattern + i) % 3) != 0;
    std::uint32_t got[L];
    V::bits(xsimd::select(V::mask(take_a), V::floats(a), V::floats(b)), got);
    for (int i = 0; i < L; ++i) {
      const std::uint32_t want = take_a[i] ? a[i] : b[i];
      ++out.lanes;
      if (got[i] != want) out.fail(lane_text(i) + "select = " + show(got[i]) + ", contract " + show(want));
    }
  });
  return out;
}

template <class Arch>
Outcome check_xsimd_compare() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  every_tuple_in_every_lane<L, 2>(special_values(), [&](const std::uint32_t* a, const std::uint32_t* b) {
    const auto x = V::floats(a), y = V::floats(b);
    bool lt[L], le[L], gt[L], ge[L], eq[L], ne[L];
    V::mask_out(x < y, lt);
    V::mask_out(x <= y, le);
    V::mask_out(x > y, gt);
    V::mask_out(x >= y, ge);
    V::mask_out(x == y, eq);
    V::mask_out(x != y, ne);
    for (int i = 0; i < L; ++i) {
      const float p = value_of_bits(a[i]), q = value_of_bits(b[i]);
      const bool want[6] = {p < q, p <= q, p > q, p >= q, p == q, p != q};
      const bool got[6] = {lt[i], le[i], gt[i], ge[i], eq[i], ne[i]};
      const char* names[6] = {"<", "<=", ">", ">=", "==", "!="};
      for (int k = 0; k < 6; ++k) {
        // != is held to IEEE only where neither operand is NaN (kernels/arch_layer.hpp).
        if (k == 5 && (std::isnan(p) || std::isnan(q))) continue;
        ++out.lanes;
        if (got[k] != want[k]) out.fail(lane_text(i) + show(a[i]) + " " + names[k] + " " + show(b[i]) + " gave " + (got[k] ? "true" : "false"));
      }
    }
  });
  return out;
}

template <class Arch>
Outcome check_xsimd_masks() {
  Outcome out;
  using V = Vec<Arch>;
  using B = typename V::B;
  constexpr int L = V::L;
  std::vector<std::array<bool, L>> masks;
  std::array<bool, L> m{};
  if (L <= 8) {
    for (unsigned bits = 0; bits < (1u << L); ++bits) {
      for (int i = 0; i < L; ++i) m[i] = (bits >> i) & 1u;
      masks.push_back(m);
    }
  } else {
    masks.push_back(m);
    for (int p = 0; p < L; ++p) {
      for (int i = 0; i < L; ++i) m[i] = i == p;
      masks.push_back(m);
      for (int i = 0; i < L; ++i) m[i] = i != p;
      masks.push_back(m);
    }
    std::mt19937 rng(53);
    for (int k = 0; k < 2000; ++k) {
      for (int i = 0; i < L; ++i) m[i] = rng() % 2 == 0;
      masks.push_back(m);
    }
  }
  bool lanes[L];
  for (bool value : {false, true}) {  // the broadcast constructor
    V::mask_out(B(value), lanes);
    for (int i = 0; i < L; ++i) {
      ++out.lanes;
      if (lanes[i] != value) out.fail(lane_text(i) + "batch_bool(" + (value ? "true" : "false") + ") differs");
    }
  }
  for (std::size_t k = 0; k < masks.size(); ++k) {
    const auto& p = masks[k];
    const auto& q = masks[(k * 7 + 3) % masks.size()];
    const B x = V::mask(p.data()), y = V::mask(q.data());
    bool any_p = false, all_p = true;
    for (int i = 0; i < L; ++i) any_p |= p[i], all_p &= p[i];
    out.lanes += 2;
    if (xsimd::any(x) != any_p) out.fail("any() of a mask gave " + std::string(any_p ? "false" : "true"));
    if (xsimd::all(x) != all_p) out.fail("all() of a mask gave " + std::string(all_p ? "false" : "true"));
    bool n[L], a[L], o[L];
    V::mask_out(~x, n);
    V::mask_out(x & y, a);
    V::mask_out(x | y, o);
    for (int i = 0; i < L; ++i) {
      out.lanes += 3;
      if (n[i] != !p[i]) out.fail(lane_text(i) + "~mask differs");
      if (a[i] != (p[i] && q[i])) out.fail(lane_text(i) + "mask & mask differs");
      if (o[i] != (p[i] || q[i])) out.fail(lane_text(i) + "mask | mask differs");
    }
  }
  return out;
}

// to_int truncates toward zero (in range); to_float rounds to nearest even.
template <class Arch>
Outcome check_xsimd_convert() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  std::vector<std::uint32_t> floats;
  for (std::uint32_t b : special_values()) {
    const float x = value_of_bits(b);
    if (x > -2147483904.0f && x < 2147483648.0f) floats.push_back(b);  // the range of int32 after truncation
  }
  for (int k = -40; k <= 40; ++k) floats.push_back(bits_of_value(static_cast<float>(k) * 0.25f));
  every_tuple_in_every_lane<L, 1>(floats, [&](const std::uint32_t* a) {
    std::int32_t got[L];
    V::ints_out(xsimd::to_int(V::floats(a)), got);
    for (int i = 0; i < L; ++i) {
      const std::int32_t want = static_cast<std::int32_t>(value_of_bits(a[i]));
      ++out.lanes;
      if (got[i] != want) out.fail(lane_text(i) + "to_int(" + show(a[i]) + ") = " + std::to_string(got[i]) + ", contract " + std::to_string(want));
    }
  });
  std::vector<std::uint32_t> ints = {0u, 1u, 0xffffffffu, 0x7fffffffu, 0x80000000u, 16777217u, 0xfeffffffu, 33554435u, 0x7fffffbfu,
                                     255u, 65535u, 16777215u};
  std::mt19937 rng(59);
  for (int k = 0; k < 2000; ++k) ints.push_back(static_cast<std::uint32_t>(rng()));
  every_tuple_in_every_lane<L, 1>(ints, [&](const std::uint32_t* a) {
    std::int32_t in[L];
    std::memcpy(in, a, sizeof in);
    std::uint32_t got[L];
    V::bits(xsimd::to_float(V::ints(in)), got);
    for (int i = 0; i < L; ++i) {
      const std::uint32_t want = bits_of_value(static_cast<float>(in[i]));
      ++out.lanes;
      if (got[i] != want) out.fail(lane_text(i) + "to_float(" + std::to_string(in[i]) + ") = " + show(got[i]) + ", contract " + show(want));
    }
  });
  return out;
}

// Wrapping integer arithmetic, bitwise operations, signed comparisons, arithmetic right and left
// shifts.
template <class Arch>
Outcome check_xsimd_integer() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  std::vector<std::uint32_t> values = {0u, 1u, 2u, 0xffu, 0x7fffffffu, 0x80000000u, 0xffffffffu, 0x12345678u, 0xfedcba98u};
  std::mt19937 rng(61);
  for (int k = 0; k < 40; ++k) values.push_back(static_cast<std::uint32_t>(rng()));
  every_tuple_in_every_lane<L, 2>(values, [&](const std::uint32_t* a, const std::uint32_t* b) {
    std::int32_t x[L], y[L];
    std::memcpy(x, a, sizeof x);
    std::memcpy(y, b, sizeof y);
    const auto p = V::ints(x), q = V::ints(y);
    using I = typename V::I;
    constexpr int kOps = 10;
    std::int32_t got[kOps][L];
    V::ints_out(p + q, got[0]);
    V::ints_out(p - q, got[1]);
    V::ints_out(p * q, got[2]);
    V::ints_out(p & q, got[3]);
    V::ints_out(p | q, got[4]);
    V::ints_out(p ^ q, got[5]);
    // Signed comparisons, read through a select (lane 1 where true, 0 where false).
    V::ints_out(xsimd::select(p < q, I(1), I(0)), got[6]);
    V::ints_out(xsimd::select(p > q, I(1), I(0)), got[7]);
    V::ints_out(xsimd::select(p == q, I(1), I(0)), got[8]);
    V::ints_out(xsimd::select(p != q, I(1), I(0)), got[9]);
    const char* names[kOps] = {"+", "-", "*", "&", "|", "^", "<", ">", "==", "!="};
    for (int i = 0; i < L; ++i) {
      const std::uint32_t want[kOps] = {a[i] + b[i], a[i] - b[i], a[i] * b[i], a[i] & b[i], a[i] | b[i], a[i] ^ b[i],
                                        x[i] < y[i], x[i] > y[i], x[i] == y[i], x[i] != y[i]};
      for (int k = 0; k < kOps; ++k) {
        ++out.lanes;
        if (static_cast<std::uint32_t>(got[k][i]) != want[k]) out.fail(lane_text(i) + show(a[i]) + " " + names[k] + " " + show(b[i]) + " differs");
      }
    }
  });
  every_tuple_in_every_lane<L, 1>(values, [&](const std::uint32_t* a) {
    std::int32_t x[L];
    std::memcpy(x, a, sizeof x);
    for (int shift = 0; shift < 32; ++shift) {
      std::int32_t right[L], left[L];
      V::ints_out(V::ints(x) >> shift, right);
      V::ints_out(V::ints(x) << shift, left);
      for (int i = 0; i < L; ++i) {
        out.lanes += 2;
        if (right[i] != (x[i] >> shift)) out.fail(lane_text(i) + show(a[i]) + " >> " + std::to_string(shift) + " is not arithmetic");
        if (static_cast<std::uint32_t>(left[i]) != (a[i] << shift)) out.fail(lane_text(i) + show(a[i]) + " << " + std::to_string(shift) + " differs");
      }
    }
  });
  return out;
}

// Float +, -, * rounded as IEEE says, and negation (used on negative lanes only).
template <class Arch>
Outcome check_xsimd_arithmetic() {
  Outcome out;
  using F = typename Vec<Arch>::F;
  auto bits = [](float x) { return bits_of_value(x); };
  auto f = [](std::uint32_t b) { return value_of_bits(b); };
  check_pairs<Arch>(out, "+", [](const F& a, const F& b) { return a + b; },
                    [&](std::uint32_t a, std::uint32_t b) { return bits(f(a) + f(b)); }, ieee_rule);
  check_pairs<Arch>(out, "-", [](const F& a, const F& b) { return a - b; },
                    [&](std::uint32_t a, std::uint32_t b) { return bits(f(a) - f(b)); }, ieee_rule);
  check_pairs<Arch>(out, "*", [](const F& a, const F& b) { return a * b; },
                    [&](std::uint32_t a, std::uint32_t b) { return bits(f(a) * f(b)); }, ieee_rule);
  std::vector<std::uint32_t> negatives;
  for (std::uint32_t b : unary_values()) {
    if (f(b) < 0.0f) negatives.push_back(b);
  }
  check_unary<Arch>(out, "-", negatives, [](const F& x) { return -x; }, [](std::uint32_t b) { return b ^ 0x80000000u; });
  return out;
}

}  // namespace
}  // namespace reproject::test
