// The arch layer's one-pixel-per-register operations (Pixel4: float RGBA and rgba16f colour)
// against their contracts (kernels/arch_layer.hpp), stated as scalar code
// (tests/arch_layer/checks.hpp). Half floats are checked for all 65,536 codes one way and around
// every code's rounding boundaries the other.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "kernels/codes.hpp"
#include "kernels/color_formats_simd.hpp"
#include "kernels/simd.hpp"
#include "tests/arch_layer/sets.hpp"
#include "tests/arch_layer/values.hpp"

namespace reproject::test {
namespace {

inline void pixel_lanes(detail::Pixel4 p, std::uint32_t* out) { std::memcpy(out, &p, 16); }
inline detail::Pixel4 pixel_of(const std::uint32_t* lanes) {
  detail::Pixel4 p;
  std::memcpy(&p, lanes, 16);
  return p;
}

template <class Arch>
Outcome check_pixel4() {
  Outcome out;
  std::uint32_t got[4];
  for (std::uint32_t v : special_values()) {
    pixel_lanes(detail::pixel4_splat(value_of_bits(v)), got);
    for (int c = 0; c < 4; ++c) {
      ++out.lanes;
      if (got[c] != v) out.fail(lane_text(c) + "pixel4_splat(" + show(v) + ") = " + show(got[c]));
    }
  }
  pixel_lanes(detail::pixel4_zero(), got);
  for (int c = 0; c < 4; ++c) {
    ++out.lanes;
    if (got[c] != 0u) out.fail(lane_text(c) + "pixel4_zero() = " + show(got[c]));
  }
  // Loads and stores at every byte offset within 16, surrounded by a sentinel.
  std::uint8_t buffer[64];
  for (int offset = 0; offset < 16; ++offset) {
    for (std::size_t first = 0; first < special_values().size(); first += 4) {
      std::uint32_t pixel[4];
      for (int c = 0; c < 4; ++c) pixel[c] = special_at(first + static_cast<std::size_t>(c));
      for (std::size_t k = 0; k < sizeof buffer; ++k) buffer[k] = static_cast<std::uint8_t>(0x71 + 3 * k);
      std::memcpy(buffer + 16 + offset, pixel, 16);
      pixel_lanes(detail::load_float4(buffer + 16 + offset), got);
      for (int c = 0; c < 4; ++c) {
        ++out.lanes;
        if (got[c] != pixel[c]) out.fail(lane_text(c) + "load_float4 at offset " + std::to_string(offset) + " = " + show(got[c]));
      }
      for (std::size_t k = 0; k < sizeof buffer; ++k) buffer[k] = static_cast<std::uint8_t>(0x71 + 3 * k);
      detail::store_float4(buffer + 16 + offset, pixel_of(pixel));
      for (std::size_t k = 0; k < sizeof buffer; ++k) {
        const std::ptrdiff_t byte = static_cast<std::ptrdiff_t>(k) - 16 - offset;
        std::uint8_t want = static_cast<std::uint8_t>(0x71 + 3 * k);
        if (byte >= 0 && byte < 16) want = reinterpret_cast<const std::uint8_t*>(pixel)[byte];
        ++out.lanes;
        if (buffer[k] != want) out.fail("store_float4 at offset " + std::to_string(offset) + ": byte " + std::to_string(byte) + " wrong");
      }
    }
  }
  return out;
}

template <class Fma>
void check_lerp4_policy(Outcome& out, const char* policy) {
  every_tuple_in_every_lane<4, 3>(special_values(), [&](const std::uint32_t* frac, const std::uint32_t* c0,
                                                        const std::uint32_t* c1) {
    std::uint32_t got[4];
    pixel_lanes(detail::lerp4<Fma>(pixel_of(frac), pixel_of(c0), pixel_of(c1)), got);
    for (int c = 0; c < 4; ++c) {
      const float f = value_of_bits(frac[c]), a = value_of_bits(c0[c]), b = value_of_bits(c1[c]);
      const float d = b - a;
      const std::uint32_t want = bits_of_value(madd_contract<Fma>(f, d, a));
      const bool inf_times_zero = (std::isinf(f) && d == 0.0f) || (f == 0.0f && std::isinf(d));
      ++out.lanes;
      if (!arithmetic_matches(want, got[c], {frac[c], bits_of_value(d), c0[c]}, !inf_times_zero)) {
        out.fail(lane_text(c) + "lerp4<" + policy + ">(" + show(frac[c]) + ", " + show(c0[c]) + ", " + show(c1[c]) + ") = " +
                 show(got[c]) + ", contract " + show(want));
      }
    }
  });
}

template <class Arch, class Fma>
Outcome check_lerp4() {
  Outcome out;
  check_lerp4_policy<Fma>(out, std::is_same<Fma, Fused>::value ? "Fused" : "Unfused");
  if constexpr (std::is_same<Fma, Fused>::value) check_lerp4_policy<Unfused>(out, "Unfused");
  return out;
}

// Lane i's two RGBA8 words when every pair of bytes (c0, c1) goes through every channel of every
// lane: in pass `shift` (0..3), of the vector whose first pair is `first` (a multiple of 4 L),
// channel c holds pair first + 4 i + (c + shift) % 4 (c0 its low byte, c1 its high one).
inline void pair_words(int shift, std::uint32_t first, int i, std::int32_t& word0, std::int32_t& word1) {
  std::uint32_t a = 0, b = 0;
  for (int c = 0; c < 4; ++c) {
    const std::uint32_t pair = (first + static_cast<std::uint32_t>(4 * i + (c + shift) % 4)) % 65536;
    a |= (pair & 0xffu) << (8 * c);
    b |= (pair >> 8) << (8 * c);
  }
  std::memcpy(&word0, &a, 4);
  std::memcpy(&word1, &b, 4);
}

// Every pair of bytes (c0, c1) in every channel of every lane, at weights from a dense sweep of
// blend fractions (their weight_q15), each lane with its own: bit for bit the scalar rule
// (kernels/codes.hpp blend_u8_q15), and within one code of the exact blend c0 + frac (c1 - c0).
template <class Arch>
Outcome check_blend_rgba8_q15() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  std::vector<float> fractions = {0.0f, 0x1p-24f, 0x1p-16f, 0x1p-15f, 0.25f, 0.5f, 0.5f - 0x1p-24f, 0.75f, 1.0f - 0x1p-24f,
                                  1.0f - 0x1p-15f, 1.0f - 0x1p-16f};
  for (int k = 1; k < 64; ++k) fractions.push_back(static_cast<float>(k * 1021 % 4096) / 4096.0f + 0x1p-14f * (k % 3));
  double worst = 0.0;
  std::int32_t words0[L], words1[L], weights[L];
  float frac[L];
  for (int shift = 0; shift < 4; ++shift) {  // each pair through every channel
    for (std::uint32_t first = 0; first < 65536; first += 4 * L) {
      for (std::size_t f = 0; f < fractions.size(); ++f) {
        for (int i = 0; i < L; ++i) {
          pair_words(shift, first, i, words0[i], words1[i]);
          frac[i] = fractions[(f + static_cast<std::size_t>(i)) % fractions.size()];
          weights[i] = detail::weight_q15(frac[i]);
        }
        std::int32_t got[L];
        V::ints_out(detail::blend_rgba8_q15<Arch>(V::ints(words0), V::ints(words1), V::ints(weights)), got);
        for (int i = 0; i < L; ++i) {
          for (int c = 0; c < 4; ++c) {
            const auto c0 = static_cast<std::uint8_t>(static_cast<std::uint32_t>(words0[i]) >> (8 * c));
            const auto c1 = static_cast<std::uint8_t>(static_cast<std::uint32_t>(words1[i]) >> (8 * c));
            const auto value = static_cast<std::uint8_t>(static_cast<std::uint32_t>(got[i]) >> (8 * c));
            const std::uint8_t want = detail::blend_u8_q15(c0, c1, weights[i]);
            const double exact = c0 + static_cast<double>(frac[i]) * (c1 - c0);
            worst = std::max(worst, std::fabs(value - exact));
            ++out.lanes;
            if (value != want || !(std::fabs(value - exact) < 1.0)) {
              out.fail(lane_text(i) + "blend_rgba8_q15 channel " + std::to_string(c) + " of " + std::to_string(c0) +
                       " and " + std::to_string(c1) + " at weight " + std::to_string(weights[i]) + " = " +
                       std::to_string(value) + ", contract " + std::to_string(want) + " (exact " + std::to_string(exact) + ")");
            }
          }
        }
      }
    }
  }
  if (!(worst < 1.0)) out.fail("the largest distance from the exact blend is " + std::to_string(worst) + " codes");
  return out;
}

// Every pair of bytes (c0, c1) in every channel of every lane: bit for bit the scalar rule
// (kernels/codes.hpp srgb_pair_near; 0xff in a far R, G or B byte, 0 elsewhere).
template <class Arch>
Outcome check_srgb_far_pairs() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  std::int32_t words0[L], words1[L], got[L];
  int far_pairs = 0;
  for (int shift = 0; shift < 4; ++shift) {  // each pair through every channel
    for (std::uint32_t first = 0; first < 65536; first += 4 * L) {
      for (int i = 0; i < L; ++i) pair_words(shift, first, i, words0[i], words1[i]);
      V::ints_out(detail::srgb_far_pairs<Arch>(V::ints(words0), V::ints(words1)), got);
      for (int i = 0; i < L; ++i) {
        for (int c = 0; c < 4; ++c) {
          const auto c0 = static_cast<std::uint8_t>(static_cast<std::uint32_t>(words0[i]) >> (8 * c));
          const auto c1 = static_cast<std::uint8_t>(static_cast<std::uint32_t>(words1[i]) >> (8 * c));
          const auto value = static_cast<std::uint8_t>(static_cast<std::uint32_t>(got[i]) >> (8 * c));
          const std::uint8_t want = c < 3 && !detail::srgb_pair_near(c0, c1) ? 0xff : 0;
          far_pairs += want != 0;
          ++out.lanes;
          if (value != want) {
            out.fail(lane_text(i) + "srgb_far_pairs channel " + std::to_string(c) + " of " + std::to_string(c0) + " and " +
                     std::to_string(c1) + " = " + std::to_string(value) + ", scalar " + std::to_string(want));
          }
        }
      }
    }
  }
  // Each pair once in each channel: R, G and B far for all but the 11,962 near pairs (the count
  // of tests/test_pixel_formats.cpp), so the rule is not vacuous either way.
  if (far_pairs != 3 * (65536 - 11962)) out.fail(std::to_string(far_pairs) + " far channel pairs, not 3 x 53,574");
  return out;
}

// Calls body(tag) with each sRGB lookup the set has (kernels/color_formats_simd.hpp: gathers, and
// permutes where has_srgb_permutes), a compile-time tag, and its name.
template <class Arch, class Body>
void for_each_srgb_lookup(const Body& body) {
  body(std::integral_constant<detail::SrgbLookup, detail::SrgbLookup::gathers>{}, "gathers: ");
  if constexpr (detail::has_srgb_permutes<Arch>()) {
    body(std::integral_constant<detail::SrgbLookup, detail::SrgbLookup::permutes>{}, "permutes: ");
  }
}

// The colour twins' sRGB decoder (kernels/color_formats_simd.hpp srgb_decode_lanes), with each
// lookup the set has: every byte in every lane, beside every other byte, bit for bit the table's
// value.
template <class Arch>
Outcome check_srgb_decode() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  const detail::SrgbTables& tables = detail::srgb_tables();
  std::int32_t bytes[L];
  std::uint32_t got[L];
  for_each_srgb_lookup<Arch>([&](auto lookup, const char* how) {
    for (int step = 1; step < 256; step += 2) {  // odd steps: every byte in every lane
      for (int first = 0; first < 256; ++first) {
        for (int i = 0; i < L; ++i) bytes[i] = (first + step * i) % 256;
        V::bits(detail::srgb_decode_lanes<Arch, decltype(lookup)::value>(tables, V::ints(bytes)), got);
        for (int i = 0; i < L; ++i) {
          std::uint32_t want = 0;
          std::memcpy(&want, &tables.to_linear[bytes[i]], 4);
          ++out.lanes;
          if (got[i] != want) {
            out.fail(lane_text(i) + how + "srgb_decode(" + std::to_string(bytes[i]) + ") = " + show(got[i]) + ", table " +
                     show(want));
          }
        }
      }
    }
  });
  return out;
}

// The colour twins' sRGB encoder (kernels/color_formats_simd.hpp: srgb_clamp_lanes, then
// srgb_table_lanes, or first srgb_estimate_lanes; not arch layer primitives, but per set like
// them), with each lookup the set has: the table's byte in every lane the scalar encoder's; where
// the lookup estimates (permutes, AVX-512), every lane's estimate that is not flagged near a
// rounding boundary the scalar byte too, for every float from the first bucket's to 1, twice:
// consecutive floats in the lanes, then lanes drawn from far apart so that a vector mixes lanes
// near and away from a boundary; with gathers every 61st float. Then zeros, negatives, values
// above 1, infinities, NaN and subnormals.
template <class Arch, class Fma>
Outcome check_srgb_encode() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  const detail::SrgbTables& tables = detail::srgb_tables();
  std::uint32_t lanes[L];
  std::int32_t got[L], estimate[L];
  float near[L];
  for_each_srgb_lookup<Arch>([&](auto lookup, const char* how) {
    constexpr detail::SrgbLookup kLookup = decltype(lookup)::value;
    auto compare = [&](const char* what) {
      const auto clamped = detail::srgb_clamp_lanes<Arch>(V::floats(lanes));
      V::ints_out(detail::srgb_table_lanes<Arch>(tables, clamped), got);
      bool estimated = false;
      if constexpr (kLookup == detail::SrgbLookup::permutes) {
        detail::IntLanes<Arch> code;
        const auto flagged = detail::srgb_estimate_lanes<Arch, Fma>(tables, clamped, code);
        V::ints_out(code, estimate);
        xsimd::select(flagged, typename V::F(1.0f), typename V::F(0.0f)).store_unaligned(near);
        estimated = true;
      }
      for (int i = 0; i < L; ++i) {
        const int want = detail::srgb_encode(tables, value_of_bits(lanes[i]));
        ++out.lanes;
        if (got[i] != want) {
          out.fail(lane_text(i) + how + what + " table srgb_encode(" + show(lanes[i]) + ") = " + std::to_string(got[i]) +
                   ", scalar " + std::to_string(want));
        }
        if (estimated && near[i] == 0.0f && estimate[i] != want) {
          out.fail(lane_text(i) + how + what + " estimated srgb_encode(" + show(lanes[i]) + ") = " +
                   std::to_string(estimate[i]) + " (not flagged near a boundary), scalar " + std::to_string(want));
        }
      }
    };
    const std::uint32_t first = detail::kSrgbFirstBucket << detail::kSrgbBucketShift, last = 0x3f800000u;  // 1.0f
    const std::uint32_t count = last - first + 1;
    const std::uint32_t stride = kLookup == detail::SrgbLookup::permutes ? 1 : 61;
    for (std::uint32_t k = 0; k < count; k += stride * L) {
      for (int i = 0; i < L; ++i) lanes[i] = first + std::min(count - 1, k + stride * static_cast<std::uint32_t>(i));
      compare("consecutive");
    }
    for (std::uint32_t k = 0; k < count; k += stride * L) {
      for (int i = 0; i < L; ++i) {
        const std::uint64_t index = k / L + static_cast<std::uint64_t>(i) * 6700417u * stride;
        lanes[i] = first + static_cast<std::uint32_t>(index % count);
      }
      compare("mixed");
    }
    for (std::size_t k = 0; k < special_values().size(); k += L) {
      for (int i = 0; i < L; ++i) lanes[i] = special_at(k + static_cast<std::size_t>(i));
      compare("special");
    }
  });
  return out;
}

// The colour twins' rgba8_srgb blend (kernels/color_formats_simd.hpp blend_rgba8; not an arch
// layer primitive, but per set like one), with each lookup the set has, in each column-fetch mode
// the set has (any two pixels; consecutive ones where it permutes): every byte the scalar
// reference's. Each channel's blend in linear light (blend_srgb_channel) against the exact
// encoding of the scalar blend, and the whole blend (blend_rgba8) against ColorRow::write's
// (blend_srgb_byte: a near pair's bytes blended as rgba8's, a pair within srgb_pair_second_order
// by srgb_second_order_blend, any other in linear light). For each code k and channel, blends
// aimed at the rounding boundary between k and k + 1 (lanes that blend k and k + 1 at a weight
// within a few float steps of where the blend crosses it), then the same pixels at weights spread
// over [0, 1]; the other channels random bytes (nearly always far pairs), then near ones (every
// pair near: the vector never leaves the bytes' blend), then pairs for the second-order blend.
// All must occur (counted below): vectors with far and near pairs, vectors of near pairs only,
// vectors whose far pairs the second-order blend takes all, and pairs that take each blend. With
// permutes, both outcomes of the estimate's test too: vectors whose estimates are wrong in some
// lane, which must take the table, and vectors with no lane near a boundary, which keep the
// estimates.
template <class Arch, class Fma>
Outcome check_srgb_blend() {
  Outcome out;
  using V = Vec<Arch>;
  constexpr int L = V::L;
  const detail::SrgbTables& tables = detail::srgb_tables();
  detail::Frame frame;
  frame.srgb = &tables;
  // boundary[k]: the least float whose byte is k + 1 (srgb_encode is monotonic in the float's bits).
  std::vector<float> boundary(255);
  for (int k = 0; k < 255; ++k) {
    std::uint32_t low = 0, high = 0x3f800000u;
    while (low < high) {
      const std::uint32_t mid = low + (high - low) / 2;
      if (detail::srgb_encode(tables, value_of_bits(mid)) > k) high = mid; else low = mid + 1;
    }
    boundary[static_cast<std::size_t>(k)] = value_of_bits(low);
  }
  long wrong_estimates = 0, kept_estimates = 0, mixed_vectors = 0, near_vectors = 0, second_order_vectors = 0,
       second_order_pairs = 0, linear_pairs = 0;
  std::uint32_t pixels[L + 1];
  float frac[L];
  std::int32_t w0[L], w1[L], got[L];
  std::uint32_t state = 0x9e3779b9u;
  auto next_byte = [&] {
    state = state * 1664525u + 1013904223u;
    return state >> 24;
  };
  for_each_srgb_lookup<Arch>([&](auto lookup, const char* how) {
    constexpr detail::SrgbLookup kLookup = decltype(lookup)::value;
    for (int channel = 0; channel < 3; ++channel) {
      for (int k = 0; k < 255; ++k) {
        constexpr int kSpread = 100;  // not a nudge: the weights spread over [0, 1], not aimed
        for (const int nudge : {-6, -3, 0, 3, 6, kSpread}) {
          for (const int others : {0, 1, 2}) {  // random bytes, near pairs, second-order pairs
            // Lane i blends pixels i and i + 1: in `channel`, k and k + 1 alternately.
            for (int i = 0; i <= L; ++i) {
              std::uint32_t p = 0;
              for (int c = 0; c < 4; ++c) {
                const std::uint32_t other = others == 0   ? next_byte()
                                            : others == 1 ? static_cast<std::uint32_t>(40 * c + 3 * (i % 3) + k % 7)
                                                          : static_cast<std::uint32_t>((i % 2 ? 100 : 150) + c + k % 5);
                const std::uint32_t byte = c == channel ? static_cast<std::uint32_t>(k + (i % 2)) : other;
                p |= byte << (8 * c);
              }
              pixels[i] = p;
            }
            for (int i = 0; i < L; ++i) {
              const float from = tables.to_linear[k + (i % 2)], to = tables.to_linear[k + 1 - (i % 2)];
              float f = static_cast<float>((static_cast<double>(boundary[static_cast<std::size_t>(k)]) - from) /
                                           (static_cast<double>(to) - from));
              for (int step = 0; nudge != kSpread && step < std::abs(nudge + i % 5); ++step) {
                f = std::nextafter(f, nudge + i % 5 > 0 ? 2.0f : -1.0f);
              }
              if (nudge == kSpread) f = (static_cast<float>(i) + 0.5f + 0.0625f * static_cast<float>(k % 16)) / static_cast<float>(L + 1);
              frac[i] = std::min(1.0f, std::max(0.0f, f));
              std::memcpy(&w0[i], &pixels[i], 4);
              std::memcpy(&w1[i], &pixels[i + 1], 4);
            }
            if constexpr (kLookup == detail::SrgbLookup::permutes) {
              bool any_near = false;
              for (int c = 0; c < 3; ++c) {
                alignas(64) float linear[L];
                for (int i = 0; i < L; ++i) {
                  const std::uint32_t c0 = pixels[i] >> (8 * c) & 0xffu, c1 = pixels[i + 1] >> (8 * c) & 0xffu;
                  linear[i] = detail::ColorRow<Fma>::blend(frac[i], tables.to_linear[c0], tables.to_linear[c1]);
                }
                std::int32_t estimate[L];
                detail::IntLanes<Arch> code;
                any_near |= xsimd::any(
                    detail::srgb_estimate_lanes<Arch, Fma>(tables, detail::srgb_clamp_lanes<Arch>(V::F::load_unaligned(linear)), code));
                V::ints_out(code, estimate);
                for (int i = 0; i < L; ++i) wrong_estimates += estimate[i] != detail::srgb_encode(tables, linear[i]);
              }
              kept_estimates += !any_near;
            }
            int far_lanes = 0, linear_lanes = 0;
            for (int i = 0; i < L; ++i) {
              bool far = false;
              for (int c = 0; c < 3; ++c) {
                const std::uint8_t c0 = pixels[i] >> (8 * c) & 0xffu, c1 = pixels[i + 1] >> (8 * c) & 0xffu;
                const bool near = detail::srgb_pair_near(c0, c1), second_order = detail::srgb_pair_second_order(c0, c1);
                far |= !near;
                second_order_pairs += !near && second_order;
                linear_lanes += !near && !second_order;
              }
              far_lanes += far;
            }
            mixed_vectors += far_lanes > 0 && far_lanes < L;
            near_vectors += far_lanes == 0;
            second_order_vectors += far_lanes > 0 && linear_lanes == 0;
            linear_pairs += linear_lanes;
            // Consecutive mode exists where the column fetch has it (sets with a permute).
            for (int consecutive = 0; consecutive < (detail::has_permute<Arch>() ? 2 : 1); ++consecutive) {
              const auto frac_lanes = V::F::load_unaligned(frac);
              const auto a = V::ints(w0), b = V::ints(w1);
              std::int32_t linear[3][L];  // each channel's blend in linear light
              auto blend_linear = [&](auto c_tag) {
                constexpr int c = decltype(c_tag)::value;
                if constexpr (detail::has_permute<Arch>()) {
                  if (consecutive) V::ints_out(detail::blend_srgb_channel<c, Arch, Fma, true, kLookup>(frame, a, b, frac_lanes), linear[c]);
                }
                if (!consecutive) V::ints_out(detail::blend_srgb_channel<c, Arch, Fma, false, kLookup>(frame, a, b, frac_lanes), linear[c]);
              };
              blend_linear(std::integral_constant<int, 0>{});
              blend_linear(std::integral_constant<int, 1>{});
              blend_linear(std::integral_constant<int, 2>{});
              if constexpr (detail::has_permute<Arch>()) {
                if (consecutive) V::ints_out(detail::blend_rgba8<Arch, Fma, true, true, kLookup>(frame, a, b, frac_lanes), got);
              }
              if (!consecutive) V::ints_out(detail::blend_rgba8<Arch, Fma, true, false, kLookup>(frame, a, b, frac_lanes), got);
              const std::string mode = std::string(how) + (consecutive ? "consecutive" : "any two");
              for (int i = 0; i < L; ++i) {
                for (int c = 0; c < 4; ++c) {
                  const std::uint8_t c0 = pixels[i] >> (8 * c) & 0xffu, c1 = pixels[i + 1] >> (8 * c) & 0xffu;
                  const std::string pair = " of " + std::to_string(c0) + " and " + std::to_string(c1) + " at " + show(bits_of_value(frac[i]));
                  if (c < 3) {
                    const int exact = detail::srgb_encode(tables, detail::ColorRow<Fma>::blend(frac[i], tables.to_linear[c0], tables.to_linear[c1]));
                    ++out.lanes;
                    if (linear[c][i] != exact) {
                      out.fail(lane_text(i) + mode + " blend_srgb_channel " + std::to_string(c) + pair + " = " +
                               std::to_string(linear[c][i]) + ", scalar " + std::to_string(exact));
                    }
                  }
                  const std::uint8_t want = c < 3 ? detail::blend_srgb_byte<Fma>(tables, c0, c1, frac[i])
                                                  : detail::blend_u8_q15(c0, c1, detail::weight_q15(frac[i]));
                  const auto value = static_cast<std::uint8_t>(static_cast<std::uint32_t>(got[i]) >> (8 * c));
                  ++out.lanes;
                  if (value != want) {
                    out.fail(lane_text(i) + mode + " blend channel " + std::to_string(c) + pair + " = " + std::to_string(value) +
                             ", scalar " + std::to_string(want));
                  }
                }
              }
            }
          }
        }
      }
    }
  });
  if constexpr (detail::has_srgb_permutes<Arch>()) {
    if (wrong_estimates == 0) out.fail("no lane's estimate was wrong: the blends do not reach the table fallback");
    if (kept_estimates == 0) out.fail("every vector had a lane near a rounding boundary: no blend kept its estimates");
  }
  if (mixed_vectors == 0) out.fail("no vector had both near and far pairs: the merge of the two blends is not reached");
  if (near_vectors == 0) out.fail("every vector had a far pair: the bytes' blend alone is not reached");
  if (second_order_pairs == 0 || linear_pairs == 0) out.fail("the second-order blend or the blend in linear light is not reached");
  if (second_order_vectors == 0) out.fail("no vector had far pairs all within the second-order blend's reach");
  return out;
}

template <class Arch>
Outcome check_load_half4() {
  Outcome out;
  std::uint8_t buffer[16];
  for (std::uint32_t first = 0; first < 65536; first += 4) {
    for (int c = 0; c < 4; ++c) detail::store_u16_at(buffer + 3 + 2 * c, static_cast<std::uint16_t>(first + c));
    std::uint32_t got[4];
    pixel_lanes(detail::load_half4(buffer + 3), got);
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t want = bits_of_value(detail::half_to_float(static_cast<std::uint16_t>(first + c)));
      ++out.lanes;
      if (got[c] != want) {
        out.fail(lane_text(c) + "load_half4 of code " + std::to_string(first + c) + " = " + show(got[c]) + ", contract " + show(want));
      }
    }
  }
  return out;
}

template <class Arch>
Outcome check_store_half4() {
  Outcome out;
  // Every half's value, the floats either side of it, and the ties halfway to the next half with
  // their neighbours; then the specials.
  std::vector<std::uint32_t> values;
  for (std::uint32_t h = 0; h < 0x7c00; ++h) {
    for (std::uint32_t sign : {0u, 0x8000u}) {
      const float v = detail::half_to_float(static_cast<std::uint16_t>(h | sign));
      const float next = detail::half_to_float(static_cast<std::uint16_t>((h + 1) | sign));
      const std::uint32_t tie = bits_of_value(v + (next - v) * 0.5f);  // exact: halves have 11 bits
      for (std::uint32_t b : {bits_of_value(v), bits_of_value(v) + 1, tie - 1, tie, tie + 1}) values.push_back(b);
      if (bits_of_value(v) & 0x7fffffffu) values.push_back(bits_of_value(v) - 1);
    }
  }
  values.insert(values.end(), special_values().begin(), special_values().end());
  std::uint8_t buffer[16];
  for (std::size_t first = 0; first < values.size(); first += 4) {
    std::uint32_t pixel[4];
    for (int c = 0; c < 4; ++c) pixel[c] = values[(first + static_cast<std::size_t>(c)) % values.size()];
    std::memset(buffer, 0x99, sizeof buffer);
    detail::store_half4(buffer + 1, pixel_of(pixel));
    for (int c = 0; c < 4; ++c) {
      const std::uint16_t want = detail::float_to_half(value_of_bits(pixel[c]));
      const std::uint16_t got = detail::load_u16_at(buffer + 1 + 2 * c);
      ++out.lanes;
      if (got != want) {
        out.fail(lane_text(c) + "store_half4(" + show(pixel[c]) + ") = code " + std::to_string(got) + ", contract " +
                 std::to_string(want));
      }
    }
    if (buffer[0] != 0x99 || buffer[9] != 0x99) out.fail("store_half4 wrote outside its 8 bytes");
  }
  return out;
}

}  // namespace
}  // namespace reproject::test
