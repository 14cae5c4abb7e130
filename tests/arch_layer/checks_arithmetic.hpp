// The arch layer's arithmetic and bit primitives against their contracts (kernels/arch_layer.hpp)
// stated as scalar code (tests/arch_layer/checks.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "kernels/codes.hpp"
#include "kernels/simd.hpp"
#include "tests/arch_layer/sets.hpp"
#include "tests/arch_layer/values.hpp"

namespace reproject::test {
namespace {

using detail::Fused;
using detail::Unfused;

inline std::string lane_text(int lane) { return "lane " + std::to_string(lane) + ": "; }

// ---- Arithmetic ----

template <class Fma>
float madd_contract(float a, float b, float c) {
  if constexpr (std::is_same<Fma, Fused>::value) return std::fma(a, b, c);
  return a * b + c;  // -ffp-contract=off: two roundings
}

// Triples whose fused and unfused results differ: c cancels the rounded product, so fma leaves
// the product's rounding error, which two roundings lose.
inline std::vector<std::uint32_t> cancelling_triples(std::mt19937& rng, int count) {
  std::uniform_real_distribution<float> unit(0.5f, 2.0f);
  std::vector<std::uint32_t> t;
  for (int k = 0; k < count; ++k) {
    const float a = unit(rng), b = unit(rng);
    t.insert(t.end(), {bits_of_value(a), bits_of_value(b), bits_of_value(-(a * b))});
  }
  return t;
}

template <class Arch, class Fma>
void check_madd_policy(Outcome& out, const char* policy) {
  using V = Vec<Arch>;
  auto check = [&](const std::uint32_t* a, const std::uint32_t* b, const std::uint32_t* c) {
    std::uint32_t got[V::L];
    V::bits(detail::vmadd<Fma>(V::floats(a), V::floats(b), V::floats(c)), got);
    for (int i = 0; i < V::L; ++i) {
      const float x = value_of_bits(a[i]), y = value_of_bits(b[i]);
      const std::uint32_t want = bits_of_value(madd_contract<Fma>(x, y, value_of_bits(c[i])));
      const bool inf_times_zero = (std::isinf(x) && y == 0.0f) || (x == 0.0f && std::isinf(y));
      ++out.lanes;
      if (!arithmetic_matches(want, got[i], {a[i], b[i], c[i]}, !inf_times_zero)) {
        out.fail(lane_text(i) + "vmadd<" + policy + ">(" + show(a[i]) + ", " + show(b[i]) + ", " + show(c[i]) + ") = " +
                 show(got[i]) + ", contract " + show(want));
      }
    }
  };
  every_tuple_in_every_lane<V::L, 3>(special_values(), check);
  std::mt19937 rng(11);
  const std::vector<std::uint32_t> t = cancelling_triples(rng, 64 * V::L);
  for (std::size_t k = 0; k + 3 * V::L <= t.size(); k += 3 * V::L) {
    std::uint32_t a[V::L], b[V::L], c[V::L];
    for (int i = 0; i < V::L; ++i) a[i] = t[k + 3 * i], b[i] = t[k + 3 * i + 1], c[i] = t[k + 3 * i + 2];
    check(a, b, c);
  }
}

template <class Arch, class Fma>
Outcome check_vmadd() {
  Outcome out;
  check_madd_policy<Arch, Fma>(out, std::is_same<Fma, Fused>::value ? "Fused" : "Unfused");
  if constexpr (std::is_same<Fma, Fused>::value) check_madd_policy<Arch, Unfused>(out, "Unfused");
  return out;
}

// A binary float operation against its scalar statement, every pair of special values in every
// lane; `rule` compares one lane.
template <class Arch, class Op, class Contract, class Rule>
void check_pairs(Outcome& out, const char* name, const Op& op, const Contract& contract, const Rule& rule) {
  using V = Vec<Arch>;
  every_tuple_in_every_lane<V::L, 2>(special_values(), [&](const std::uint32_t* a, const std::uint32_t* b) {
    std::uint32_t got[V::L];
    V::bits(op(V::floats(a), V::floats(b)), got);
    for (int i = 0; i < V::L; ++i) {
      const std::uint32_t want = contract(a[i], b[i]);
      ++out.lanes;
      if (!rule(a[i], b[i], want, got[i])) {
        out.fail(lane_text(i) + name + "(" + show(a[i]) + ", " + show(b[i]) + ") = " + show(got[i]) + ", contract " + show(want));
      }
    }
  });
}

inline bool ieee_rule(std::uint32_t a, std::uint32_t b, std::uint32_t want, std::uint32_t got) {
  return arithmetic_matches(want, got, {a, b});
}
inline bool exact_rule(std::uint32_t, std::uint32_t, std::uint32_t want, std::uint32_t got) { return want == got; }

template <class Arch>
Outcome check_vdiv() {
  Outcome out;
  using F = typename Vec<Arch>::F;
  check_pairs<Arch>(
      out, "vdiv", [](const F& a, const F& b) { return detail::vdiv(a, b); },
      [](std::uint32_t a, std::uint32_t b) { return bits_of_value(value_of_bits(a) / value_of_bits(b)); }, ieee_rule);
  return out;
}

template <class Arch>
Outcome check_vmin() {
  Outcome out;
  using F = typename Vec<Arch>::F;
  check_pairs<Arch>(
      out, "vmin", [](const F& a, const F& b) { return detail::vmin(a, b); },
      [](std::uint32_t a, std::uint32_t b) { return value_of_bits(a) < value_of_bits(b) ? a : b; }, exact_rule);
  return out;
}
template <class Arch>
Outcome check_vmax() {
  Outcome out;
  using F = typename Vec<Arch>::F;
  check_pairs<Arch>(
      out, "vmax", [](const F& a, const F& b) { return detail::vmax(a, b); },
      [](std::uint32_t a, std::uint32_t b) { return value_of_bits(a) > value_of_bits(b) ? a : b; }, exact_rule);
  return out;
}

// Values for the unary checks: the specials, quarters from -10 to 10, and random floats of every
// exponent.
inline std::vector<std::uint32_t> unary_values() {
  std::vector<std::uint32_t> v = special_values();
  for (int k = -40; k <= 40; ++k) v.push_back(bits_of_value(static_cast<float>(k) * 0.25f));
  std::mt19937 rng(5);
  for (int k = 0; k < 4000; ++k) v.push_back(static_cast<std::uint32_t>(rng()));
  return v;
}

template <class Arch, class Op, class Contract>
void check_unary(Outcome& out, const char* name, const std::vector<std::uint32_t>& values, const Op& op,
                 const Contract& contract) {
  using V = Vec<Arch>;
  every_tuple_in_every_lane<V::L, 1>(values, [&](const std::uint32_t* a) {
    std::uint32_t got[V::L];
    V::bits(op(V::floats(a)), got);
    for (int i = 0; i < V::L; ++i) {
      const std::uint32_t want = contract(a[i]);
      ++out.lanes;
      if (got[i] != want) out.fail(lane_text(i) + name + "(" + show(a[i]) + ") = " + show(got[i]) + ", contract " + show(want));
    }
  });
}

template <class Arch>
Outcome check_vfloor() {
  Outcome out;
  using F = typename Vec<Arch>::F;
  check_unary<Arch>(out, "vfloor", unary_values(), [](const F& x) { return detail::vfloor(x); },
                    [](std::uint32_t x) { return is_nan_bits(x) ? quieted(x) : bits_of_value(std::floor(value_of_bits(x))); });
  return out;
}

template <class Arch>
Outcome check_round_to_int() {
  Outcome out;
  using V = Vec<Arch>;
  std::vector<std::uint32_t> values;
  for (std::uint32_t b : unary_values()) {
    const float x = value_of_bits(b);
    if (x >= -2147483648.0f && x < 2147483648.0f) values.push_back(b);  // the contract's range (no NaN)
  }
  for (int k = -20; k <= 20; ++k) values.push_back(bits_of_value(static_cast<float>(k) + 0.5f));  // ties
  for (float big : {4194304.5f, 4194305.5f, -4194304.5f, -4194305.5f}) values.push_back(bits_of_value(big));
  every_tuple_in_every_lane<V::L, 1>(values, [&](const std::uint32_t* a) {
    std::int32_t got[V::L];
    V::ints_out(detail::round_to_int<Arch>(V::floats(a)), got);
    for (int i = 0; i < V::L; ++i) {
      const std::int32_t want = static_cast<std::int32_t>(std::nearbyint(static_cast<double>(value_of_bits(a[i]))));
      ++out.lanes;
      if (got[i] != want) {
        out.fail(lane_text(i) + "round_to_int(" + show(a[i]) + ") = " + std::to_string(got[i]) + ", contract " +
                 std::to_string(want));
      }
    }
  });
  return out;
}

// ---- Bits ----

template <class Arch>
Outcome check_bits_of() {
  Outcome out;
  using V = Vec<Arch>;
  every_tuple_in_every_lane<V::L, 1>(unary_values(), [&](const std::uint32_t* a) {
    std::int32_t got[V::L];
    V::ints_out(detail::bits_of<Arch>(V::floats(a)), got);
    for (int i = 0; i < V::L; ++i) {
      ++out.lanes;
      if (static_cast<std::uint32_t>(got[i]) != a[i]) out.fail(lane_text(i) + "bits_of(" + show(a[i]) + ") changed the bits");
    }
  });
  return out;
}
template <class Arch>
Outcome check_float_bits() {
  Outcome out;
  using V = Vec<Arch>;
  every_tuple_in_every_lane<V::L, 1>(unary_values(), [&](const std::uint32_t* a) {
    std::int32_t in[V::L];
    std::memcpy(in, a, sizeof in);
    std::uint32_t got[V::L];
    V::bits(detail::float_bits<Arch>(V::ints(in)), got);
    for (int i = 0; i < V::L; ++i) {
      ++out.lanes;
      if (got[i] != a[i]) out.fail(lane_text(i) + "float_bits(" + show(a[i]) + ") = " + show(got[i]));
    }
  });
  return out;
}

template <class Arch>
Outcome check_byte_lanes() {
  Outcome out;
  using V = Vec<Arch>;
  std::vector<std::uint32_t> words;
  const std::uint32_t bytes[] = {0x00, 0x01, 0x7f, 0x80, 0xfe, 0xff};
  for (std::uint32_t b0 : bytes)
    for (std::uint32_t b1 : bytes)
      for (std::uint32_t b2 : bytes)
        for (std::uint32_t b3 : bytes) words.push_back(b0 | b1 << 8 | b2 << 16 | b3 << 24);
  auto one = [&](auto byte_tag) {
    constexpr int kByte = decltype(byte_tag)::value;
    every_tuple_in_every_lane<V::L, 1>(words, [&](const std::uint32_t* w) {
      std::int32_t in[V::L], got[V::L];
      std::memcpy(in, w, sizeof in);
      V::ints_out(detail::byte_lanes<kByte, Arch>(V::ints(in)), got);
      for (int i = 0; i < V::L; ++i) {
        const std::int32_t want = static_cast<std::int32_t>((w[i] >> (8 * kByte)) & 0xffu);
        ++out.lanes;
        if (got[i] != want) {
          out.fail(lane_text(i) + "byte_lanes<" + std::to_string(kByte) + ">(" + show(w[i]) + ") = " + std::to_string(got[i]) +
                   ", contract " + std::to_string(want));
        }
      }
    });
  };
  one(std::integral_constant<int, 0>{});
  one(std::integral_constant<int, 1>{});
  one(std::integral_constant<int, 2>{});
  one(std::integral_constant<int, 3>{});
  return out;
}

}  // namespace
}  // namespace reproject::test
