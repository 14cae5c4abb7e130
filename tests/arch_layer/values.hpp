// The values the arch layer's checks put in every lane (tests/arch_layer/checks.hpp): special
// floats as bit patterns, the NaN rules of the contracts, vectors to and from lanes, and the
// loops that place every pair or triple of values in every lane position.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>
#include <xsimd/xsimd.hpp>

namespace reproject::test {
namespace {

inline std::uint32_t bits_of_value(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}
inline float value_of_bits(std::uint32_t b) {
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}
inline bool is_nan_bits(std::uint32_t b) { return (b & 0x7fffffffu) > 0x7f800000u; }
inline std::uint32_t quieted(std::uint32_t b) { return b | 0x00400000u; }

inline std::string show(std::uint32_t b) {
  char text[64];
  std::snprintf(text, sizeof text, "0x%08x (%.9g)", static_cast<unsigned>(b), static_cast<double>(value_of_bits(b)));
  return text;
}

// Zeros and infinities of both signs; quiet NaNs of both signs with and without payloads;
// signalling NaNs (the bit-moving primitives must keep them, arithmetic quiets them); denormals;
// the normal and finite limits; rounding ties; the integer-conversion limits; ordinary values.
inline const std::vector<std::uint32_t>& special_values() {
  static const std::vector<std::uint32_t> values = [] {
    std::vector<std::uint32_t> v = {
        0x00000000u, 0x80000000u, 0x7f800000u, 0xff800000u,               // +-0, +-inf
        0x7fc00000u, 0xffc00000u, 0x7fc12345u, 0xffd54321u,               // quiet NaNs
        0x7f800001u, 0xff812345u,                                         // signalling NaNs
        0x00000001u, 0x80000001u, 0x007fffffu, 0x807fffffu,               // denormals
        0x00800000u, 0x80800000u, 0x7f7fffffu, 0xff7fffffu,               // smallest normal, largest finite
    };
    const float ordinary[] = {1.0f,        -1.0f,       0.5f,        -0.5f,       1.5f,          -1.5f,
                              2.5f,        -2.5f,       0.25f,       -0.25f,      0.49999997f,   -0.49999997f,
                              8388607.5f,  -8388607.5f, 8388608.0f,  8388609.0f,  16777216.0f,   16777218.0f,
                              2147483520.0f, -2147483648.0f, 2147483648.0f, -2147483904.0f, 3.0f, 7.0f,
                              1.0f / 3.0f, 3.14159274f, 100.25f,     -1e20f,      1e-30f,        65504.0f,
                              65520.0f,    0x1p-14f,    0x1p-24f,    255.0f,      254.5f,        -7.75f};
    for (float f : ordinary) v.push_back(bits_of_value(f));
    return v;
  }();
  return values;
}

// The IEEE result rule of kernels/arch_layer.hpp (vmadd): bit for bit where the result is a
// number; where it is NaN, a NaN, and when the NaN operands are one NaN (quieted alike) that NaN
// quieted (unless `propagates` is false: the contract leaves that case open).
inline bool arithmetic_matches(std::uint32_t expected, std::uint32_t got, std::initializer_list<std::uint32_t> operands,
                               bool propagates = true) {
  if (!is_nan_bits(expected)) return got == expected;
  if (!is_nan_bits(got)) return false;
  if (!propagates) return true;
  bool one_nan = true;
  std::uint32_t nan = 0;
  for (std::uint32_t o : operands) {
    if (!is_nan_bits(o)) continue;
    if (nan != 0 && quieted(o) != nan) one_nan = false;
    nan = quieted(o);
  }
  return nan == 0 || !one_nan || got == nan;
}

// Vectors of one set to and from plain lanes (aligned stores and loads move bits unchanged).
template <class Arch>
struct Vec {
  using F = xsimd::batch<float, Arch>;
  using I = xsimd::batch<std::int32_t, Arch>;
  using B = xsimd::batch_bool<float, Arch>;
  static constexpr int L = static_cast<int>(F::size);

  static F floats(const std::uint32_t* bits) {
    alignas(64) float lanes[L];
    std::memcpy(lanes, bits, sizeof lanes);
    return F::load_aligned(lanes);
  }
  static void bits(const F& v, std::uint32_t* out) {
    alignas(64) float lanes[L];
    v.store_aligned(lanes);
    std::memcpy(out, lanes, sizeof lanes);
  }
  static I ints(const std::int32_t* values) {
    alignas(64) std::int32_t lanes[L];
    std::memcpy(lanes, values, sizeof lanes);
    return I::load_aligned(lanes);
  }
  static void ints_out(const I& v, std::int32_t* out) {
    alignas(64) std::int32_t lanes[L];
    v.store_aligned(lanes);
    std::memcpy(out, lanes, sizeof lanes);
  }
  static B mask(const bool* set) {
    alignas(64) float lanes[L];
    for (int i = 0; i < L; ++i) lanes[i] = set[i] ? 1.0f : 0.0f;
    return F::load_aligned(lanes) == F(1.0f);
  }
  static void mask_out(const B& m, bool* out) {
    alignas(64) float lanes[L];
    xsimd::select(m, F(1.0f), F(0.0f)).store_aligned(lanes);
    for (int i = 0; i < L; ++i) out[i] = lanes[i] != 0.0f;
  }
};

// body(lanes of operand 0, lanes of operand 1, ...) over vectors in which every tuple of `values`
// (Arity of them: values^Arity tuples) sits once in each lane position: the tuples run through
// the lanes in order, shifted by one lane per pass, L passes.
template <int L, int Arity, class Body>
void every_tuple_in_every_lane(const std::vector<std::uint32_t>& values, const Body& body) {
  const std::size_t n = values.size();
  std::size_t tuples = 1;
  for (int k = 0; k < Arity; ++k) tuples *= n;
  std::uint32_t lanes[Arity][L];
  for (int shift = 0; shift < L; ++shift) {
    for (std::size_t first = 0; first < tuples; first += L) {
      for (int i = 0; i < L; ++i) {
        std::size_t t = (first + static_cast<std::size_t>(i + shift)) % tuples;
        for (int k = Arity - 1; k >= 0; --k) {
          lanes[k][i] = values[t % n];
          t /= n;
        }
      }
      if constexpr (Arity == 1) body(lanes[0]);
      if constexpr (Arity == 2) body(lanes[0], lanes[1]);
      if constexpr (Arity == 3) body(lanes[0], lanes[1], lanes[2]);
    }
  }
}

}  // namespace
}  // namespace reproject::test
