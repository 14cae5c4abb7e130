// Engine-native pixel formats (reproject/formats.hpp, docs/BEHAVIOUR.md "Pixel formats"):
//  * the conversions, exhaustively where cheap (every half, every D16 code, a dense D24 sweep,
//    the seed's packed-RGBA8 depth round trip, sRGB against double precision);
//  * every method x arch x format: SIMD bit-identical to the scalar reference, 1 thread = 2;
//  * every method x format against the float path on the same frame: identical status and
//    source x, colour and depth within 1 LSB of the float result rounded into the format.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <limits>
#include <random>
#include <vector>

#include "kernels/codes.hpp"
#include "kernels/color_formats.hpp"
#include "kernels/dispatch.hpp"
#include "kernels/frame.hpp"
#include "src/reproject_internal.hpp"
#include "reproject/reproject.hpp"
#include "support/arch_report.hpp"
#include "tests/arch_layer/sets.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#include <immintrin.h>
#elif defined(__aarch64__)
#include <arm_neon.h>
#endif

namespace reproject {
namespace {

float bits_float(std::uint32_t b) {
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}
std::uint32_t float_bits(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

// ---- conversions ----------------------------------------------------------------------------

// The processor's own half-float conversions, which the library's software ones (the scalar
// references, and every set without a hardware conversion) must equal bit for bit: F16C on x86,
// where not every CPU has it; FCVTL/FCVTN on AArch64, where every processor has them (with the
// default FPCR: IEEE halves, round to nearest even, subnormals kept, NaN payloads kept).
#if defined(__x86_64__) || defined(__i386__)
const char* const kHardwareHalf = "F16C";
bool hardware_half_available() {
  // F16C's instructions are VEX-encoded: usable only where AVX is, which includes the operating
  // system's support for the AVX state (GCC's and Clang's "avx" check XGETBV too).
  unsigned a = 0, b = 0, c = 0, d = 0;
  return __builtin_cpu_supports("avx") && __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C) != 0;
}
__attribute__((target("f16c"))) float hardware_half_to_float(std::uint16_t h) {
  return _mm_cvtss_f32(_mm_cvtph_ps(_mm_cvtsi32_si128(h)));
}
__attribute__((target("f16c"))) std::uint16_t hardware_float_to_half(float f) {
  return static_cast<std::uint16_t>(_mm_extract_epi16(_mm_cvtps_ph(_mm_set_ss(f), _MM_FROUND_TO_NEAREST_INT), 0));
}
#elif defined(__aarch64__)
const char* const kHardwareHalf = "AArch64 FCVTL/FCVTN";
bool hardware_half_available() { return true; }
float hardware_half_to_float(std::uint16_t h) {
  return vgetq_lane_f32(vcvt_f32_f16(vreinterpret_f16_u16(vdup_n_u16(h))), 0);
}
std::uint16_t hardware_float_to_half(float f) {
  return vget_lane_u16(vreinterpret_u16_f16(vcvt_f16_f32(vdupq_n_f32(f))), 0);
}
#else
const char* const kHardwareHalf = nullptr;
bool hardware_half_available() { return false; }
float hardware_half_to_float(std::uint16_t) { return 0.0f; }
std::uint16_t hardware_float_to_half(float) { return 0; }
#endif

TEST(PixelFormats, HalfConversionsMatchTheProcessor) {
  if (kHardwareHalf == nullptr) GTEST_SKIP() << "no hardware half-float conversion known on this processor to compare with";
  if (!hardware_half_available()) GTEST_SKIP() << "no " << kHardwareHalf << " on this CPU to compare with";
  long compared = 0;
  for (std::uint32_t h = 0; h < 65536; ++h) {
    const float mine = formats::half_to_float(static_cast<std::uint16_t>(h));
    ASSERT_EQ(float_bits(mine), float_bits(hardware_half_to_float(static_cast<std::uint16_t>(h)))) << "half " << h;
    // Every half's value, and the midpoints around it (the ties), back to half.
    for (std::uint32_t step : {0u, 0x1000u, 0xfffu, 0x1001u, 0x2000u}) {
      const float f = bits_float(float_bits(mine) + step);
      ASSERT_EQ(formats::float_to_half(f), hardware_float_to_half(f)) << "float " << f << " bits " << std::hex << float_bits(f);
      compared += 2;
    }
  }
  std::mt19937 rng(3);
  for (int i = 0; i < 4000000; ++i) {
    const float f = bits_float(static_cast<std::uint32_t>(rng()));
    ASSERT_EQ(formats::float_to_half(f), hardware_float_to_half(f)) << "float bits " << std::hex << float_bits(f);
    ++compared;
  }
  std::printf("half: %ld conversions equal to %s\n", compared, kHardwareHalf);
}

TEST(PixelFormats, Unorm16EveryCode) {
  for (std::uint32_t u = 0; u < 65536; ++u) {
    const float d = formats::unorm_to_float(u, 16);
    ASSERT_EQ(d, static_cast<float>(static_cast<double>(u) / 65535.0)) << u;  // correctly rounded
    ASSERT_EQ(formats::float_to_unorm(d, 16), u) << u;
  }
  EXPECT_EQ(formats::float_to_unorm(-1.0f, 16), 0u);
  EXPECT_EQ(formats::float_to_unorm(2.0f, 16), 65535u);
  EXPECT_EQ(formats::float_to_unorm(std::numeric_limits<float>::quiet_NaN(), 16), 0u);
  // Ties to even: 0.5 / 65535 and 1.5 / 65535 (exact halves in float at this scale).
  EXPECT_EQ(formats::float_to_unorm(static_cast<float>(2.5 / 65535.0), 16), 2u);
}

TEST(PixelFormats, Unorm24DenseSweep) {
  long checked = 0, off = 0;
  for (std::uint32_t u = 0; u < (1u << 24); u += (u < 70000 || u > (1u << 24) - 70000) ? 1 : 7) {
    const float d = formats::unorm_to_float(u, 24);
    ASSERT_EQ(d, static_cast<float>(static_cast<double>(u) / 16777215.0)) << u;
    const std::uint32_t back = formats::float_to_unorm(d, 24);
    // A float has 24 significant bits: near 1 the round trip can land one code off.
    ASSERT_LE(back > u ? back - u : u - back, 1u) << u;
    off += back != u;
    ++checked;
  }
  std::printf("unorm24: %ld codes, %ld round trips one code off\n", checked, off);
  EXPECT_LT(off, checked / 100);
}

// The kernels' own depth loads (the SIMD decode computes u / (2^b - 1) without a division where
// it has an FMA): every D16 and D24 code, through each arch's decode, gives the correctly
// rounded quotient (the decode writes the stored values it read for the resolve).
TEST(PixelFormats, UnormDecodeEveryCodeEveryArch) {
  const int width = 65536;
  std::vector<std::uint8_t> row(static_cast<std::size_t>(width) * 4);
  std::vector<float> parallax(width), stored(width), color(width);
  long checked = 0;
  for (DepthFormat format : {DepthFormat::unorm16, DepthFormat::unorm24_s8, DepthFormat::s8_unorm24}) {
    SourceView source;
    source.depth_buffer = DepthBuffer::of(format, row.data(), width, 1, width * 4);
    source.color = ColorView::planar({FloatPlane{color.data(), width, 1, width}});
    TargetView target;
    const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 100.0);
    const detail::Frame f = detail::plan_frame(source, decoder, ParallaxModel{3.0f, -30.0f}, Options(), target);
    const int chunks = format == DepthFormat::unorm16 ? 1 : 256;
    for (int a = 0; a < kArchCount; ++a) {
      if (!arch_supported(static_cast<Arch>(a))) continue;
      const detail::KernelTable& kernels = *detail::compiled_kernels(static_cast<Arch>(a));
      for (int chunk = 0; chunk < chunks; ++chunk) {
        for (int x = 0; x < width; ++x) {
          const std::uint32_t u = static_cast<std::uint32_t>(chunk) * width + static_cast<std::uint32_t>(x);
          if (format == DepthFormat::unorm16) {
            const std::uint16_t v = static_cast<std::uint16_t>(u);
            std::memcpy(row.data() + 2 * x, &v, 2);
          } else {
            const std::uint32_t w = format == DepthFormat::unorm24_s8 ? (u | 0xa5000000u) : (u << 8 | 0x5au);
            std::memcpy(row.data() + 4 * x, &w, 4);
          }
        }
        kernels.decode(f, row.data(), parallax.data(), stored.data());
        const double max = format == DepthFormat::unorm16 ? 65535.0 : 16777215.0;
        for (int x = 0; x < width; ++x) {
          const std::uint32_t u = static_cast<std::uint32_t>(chunk) * width + static_cast<std::uint32_t>(x);
          ASSERT_EQ(stored[static_cast<std::size_t>(x)], static_cast<float>(u / max))
              << to_string(static_cast<Arch>(a)) << " " << to_string(format) << " code " << u;
          ++checked;
        }
      }
    }
  }
  std::printf("unorm decode: %ld codes through the kernels, all correctly rounded\n", checked);
}

// The seed's shader packing (EncUnitRangeToRGBA8) as a GPU evaluates it in float, the R, G, B
// channels quantised by an UNORM8 render target (round to nearest).
void seed_pack(float v, std::uint8_t rgb[3]) {
  const float scaled[4] = {v, v * 255.0f, v * 65025.0f, v * 16581375.0f};
  float enc[4];
  for (int i = 0; i < 4; ++i) enc[i] = scaled[i] - std::floor(scaled[i]);
  for (int i = 0; i < 3; ++i) enc[i] -= enc[i + 1] * (1.0f / 255.0f);
  for (int i = 0; i < 3; ++i) rgb[i] = static_cast<std::uint8_t>(std::lround(std::min(std::max(enc[i], 0.0f), 1.0f) * 255.0f));
}

TEST(PixelFormats, PackedLinearRoundTrip) {
  constexpr double kStep = 1.0 / 16581375.0;  // the three bytes' resolution
  double worst_seed = 0.0, worst_own = 0.0;
  for (int i = 0; i < 2000000; ++i) {
    const float v = static_cast<float>(i) / 2000000.0f + 1.3e-8f * static_cast<float>(i % 7);
    std::uint8_t rgb[3];
    seed_pack(v, rgb);
    worst_seed = std::max(worst_seed, std::fabs(formats::packed_linear_value(rgb) - static_cast<double>(v)));
    formats::pack_linear_value(v, rgb);
    worst_own = std::max(worst_own, std::fabs(formats::packed_linear_value(rgb) - static_cast<double>(v)));
  }
  std::printf("packed linear: worst |decode - v| seed packing %.3f steps, own %.3f steps\n", worst_seed / kStep,
              worst_own / kStep);
  // The seed's float evaluation loses what float cannot hold of v * 16581375 (and its B byte
  // carries the rounding of the G step): within 2 steps of the three bytes, i.e. ~1.2e-7.
  EXPECT_LT(worst_seed, 2.0 * kStep);
  EXPECT_LT(worst_own, 1.0 * kStep);  // half a step plus float rounding of v
}

double srgb_decode_double(double e) { return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4); }
double srgb_encode_double(double l) { return l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055; }
int srgb_byte_double(double l) {
  l = std::min(std::max(l, 0.0), 1.0);
  return static_cast<int>(std::floor(255.0 * srgb_encode_double(l) + 0.5));
}

// rgba8's fixed-point blend (docs/BEHAVIOUR.md "Pixel formats") against the exact blend of the
// byte values, c0 + frac (c1 - c0), for every difference c1 - c0 and every weight (the result
// depends on c0 only through the sum, and on frac only through its weight; the exact blend is
// linear in frac, so the ends of each weight's range of frac bound it): within one code.
TEST(PixelFormats, Rgba8FixedPointWithinOneCodeOfTheExactBlend) {
  double worst = 0.0;
  long checked = 0;
  for (int d = -255; d <= 255; ++d) {
    for (std::int32_t w = 0; w < 32768; ++w) {
      const std::uint8_t c0 = static_cast<std::uint8_t>(d < 0 ? 255 : 0);
      const std::uint8_t c1 = static_cast<std::uint8_t>(c0 + d);
      const int got = detail::blend_u8_q15(c0, c1, w) - c0;
      const double low = static_cast<double>(d) * w / 32768.0, high = static_cast<double>(d) * (w + 1) / 32768.0;
      worst = std::max({worst, std::fabs(got - low), std::fabs(got - high)});
      ++checked;
      // The weight of frac is floor(frac 2^15): both ends of its range map to it.
      ASSERT_EQ(detail::weight_q15(static_cast<float>(w) / 32768.0f), w);
      ASSERT_EQ(detail::weight_q15(std::nextafter(static_cast<float>(w + 1) / 32768.0f, 0.0f)), w);
    }
  }
  std::printf("rgba8 fixed point: %ld (difference, weight) pairs, at most %.6f codes from the exact blend\n", checked,
              worst);
  EXPECT_LT(worst, 1.0);
  EXPECT_LE(worst, 0.5 + 255.0 / 32768.0 + 1e-12);  // rounding, plus the weight's truncation
}

TEST(PixelFormats, SrgbAgainstDoublePrecision) {
  for (int k = 0; k < 256; ++k) {
    ASSERT_EQ(formats::srgb_to_linear(static_cast<std::uint8_t>(k)), static_cast<float>(srgb_decode_double(k / 255.0))) << k;
    ASSERT_EQ(formats::linear_to_srgb(formats::srgb_to_linear(static_cast<std::uint8_t>(k))), k) << k;
  }
  // Encoding: every float in [0, 1] with a mantissa step of 2^7 ulps (and values around it) is
  // the double-precision byte exactly.
  long encoded = 0;
  for (std::uint32_t b = 0; b <= float_bits(1.0f); b += 128) {
    const float l = bits_float(b);
    ASSERT_EQ(formats::linear_to_srgb(l), srgb_byte_double(l)) << l;
    ++encoded;
  }
  EXPECT_EQ(formats::linear_to_srgb(-0.5f), 0);
  EXPECT_EQ(formats::linear_to_srgb(7.0f), 255);
  // Every NaN is 0: quiet and signalling, either sign (clang for AArch64 once quieted a
  // signalling NaN into the clamp's other end, 255: kernels/color_formats.hpp).
  for (const std::uint32_t nan : {0x7fc00000u, 0xffc00000u, 0x7f800001u, 0xff812345u, 0x7fbfffffu}) {
    EXPECT_EQ(formats::linear_to_srgb(bits_float(nan)), 0) << std::hex << nan;
    EXPECT_EQ(formats::float_to_unorm(bits_float(nan), 8), 0u) << std::hex << nan;
    EXPECT_EQ(formats::float_to_unorm(bits_float(nan), 24), 0u) << std::hex << nan;
  }
  // Blending: the library's rule (the bytes' linear floats blended in float, then encoded)
  // against the same blend in double: equal but where the float blend lands within rounding of
  // a byte boundary.
  std::mt19937 rng(11);
  long blends = 0, differ = 0;
  for (int i = 0; i < 1000000; ++i) {
    const int c0 = static_cast<int>(rng() % 256), c1 = static_cast<int>(rng() % 256);
    const float frac = static_cast<float>(rng() % 4096) / 4096.0f;
    const float l0 = formats::srgb_to_linear(static_cast<std::uint8_t>(c0));
    const float l1 = formats::srgb_to_linear(static_cast<std::uint8_t>(c1));
    const int mine = formats::linear_to_srgb(std::fma(frac, l1 - l0, l0));
    const double exact = srgb_decode_double(c0 / 255.0) + frac * (srgb_decode_double(c1 / 255.0) - srgb_decode_double(c0 / 255.0));
    const int reference = srgb_byte_double(exact);
    ASSERT_LE(std::abs(mine - reference), 1) << c0 << " " << c1 << " " << frac;
    differ += mine != reference;
    ++blends;
  }
  std::printf("sRGB: %ld encodes exact; %ld blends, %ld one byte off the double reference\n", encoded, blends, differ);
  EXPECT_LT(differ, blends / 1000);
}

// rgba8_srgb's blend of an R, G or B byte (kernels/color_formats.hpp blend_srgb_byte; docs/
// BEHAVIOUR.md "Pixel formats") against the byte nearest the exact blend of the exact linear
// values, in double: within one code for all 65,536 pairs of bytes, with both FMA policies. The
// fracs: both ends of each weight's range (the exact blend is monotonic in frac, the bytes' blend
// constant over the range), every 13th weight for the near pairs (blended as bytes), every 29th
// for the second-order ones (srgb_second_order_blend, which also stays between the two bytes) and
// every 61st for the others (the blend in linear light, also tested above); each bound was checked at every
// weight (40 s) when it was chosen, the second-order one also between the weights (both blends
// are monotonic in frac). The near rule admits exactly 11,962 pairs and the second-order rule
// 23,072 more; each rule one code looser (d <= 11 + (min + 4) / 8, d <= min + 10) breaks the
// bound for some of the pairs it would add (checked at every weight).
TEST(PixelFormats, SrgbBlendWithinOneCodeOfTheExactBlend) {
  const detail::SrgbTables& tables = detail::srgb_tables();
  double linear[256], threshold[256];  // threshold[k]: the least linear value whose byte is k
  for (int c = 0; c < 256; ++c) linear[c] = srgb_decode_double(c / 255.0);
  for (int k = 1; k < 256; ++k) threshold[k] = srgb_decode_double((k - 0.5) / 255.0);
  auto nearest = [&](double l) { return static_cast<int>(std::upper_bound(threshold + 1, threshold + 256, l) - (threshold + 1)); };
  enum Kind { kNear, kSecondOrder, kLinear };
  long pairs[3] = {}, blends[3] = {}, exact[3] = {}, near_looser_breaks = 0, second_order_looser_breaks = 0;
  int worst[3] = {};
  for (int c0 = 0; c0 < 256; ++c0) {
    for (int c1 = 0; c1 < 256; ++c1) {
      const auto b0 = static_cast<std::uint8_t>(c0), b1 = static_cast<std::uint8_t>(c1);
      const Kind kind = detail::srgb_pair_near(b0, b1) ? kNear : detail::srgb_pair_second_order(b0, b1) ? kSecondOrder : kLinear;
      ++pairs[kind];
      const int d = std::abs(c1 - c0), low = std::min(c0, c1);
      // In a rule one code looser, not in this one: the bytes' blend, or the second-order one.
      const bool near_looser = d == 11 + ((low + 4) >> 3);
      const bool second_order_looser = kind == kLinear && d == low + 10;
      const int stride = near_looser || second_order_looser ? 1 : kind == kNear ? 13 : kind == kSecondOrder ? 29 : 61;
      bool near_broke = false, second_order_broke = false;
      for (std::int32_t w = 0; w < 32768; w += stride) {
        for (const float frac : {static_cast<float>(w) / 32768.0f, std::nextafter(static_cast<float>(w + 1) / 32768.0f, 0.0f)}) {
          const int want = nearest(linear[c0] + static_cast<double>(frac) * (linear[c1] - linear[c0]));
          if (near_looser) near_broke |= std::abs(detail::blend_u8_q15(b0, b1, w) - want) > 1;
          if (second_order_looser) second_order_broke |= std::abs(detail::srgb_second_order_blend(b0, b1, frac) - want) > 1;
          if (stride == 1) continue;
          for (int policy = 0; policy < (kind == kLinear ? 2 : 1); ++policy) {  // only the linear blend has an FMA
            const int got = policy == 0 ? detail::blend_srgb_byte<detail::Fused>(tables, b0, b1, frac)
                                        : detail::blend_srgb_byte<detail::Unfused>(tables, b0, b1, frac);
            worst[kind] = std::max(worst[kind], std::abs(got - want));
            exact[kind] += got == want;
            ++blends[kind];
            ASSERT_LE(std::abs(got - want), 1) << c0 << " " << c1 << " at weight " << w << " frac " << frac;
            ASSERT_TRUE(got >= low && got <= low + d) << c0 << " " << c1 << " at frac " << frac << ": " << got;
          }
        }
      }
      near_looser_breaks += near_broke;
      second_order_looser_breaks += second_order_broke;
    }
  }
  const char* names[3] = {"near (bytes)", "second-order", "linear light"};
  for (int k = 0; k < 3; ++k) {
    std::printf("rgba8_srgb blend, %-12s: %5ld pairs, %ld blends, %.1f %% the nearest byte, at most %d off\n", names[k],
                pairs[k], blends[k], 100.0 * static_cast<double>(exact[k]) / static_cast<double>(blends[k]), worst[k]);
  }
  std::printf("rules one code looser break at %ld (near) and %ld (second-order) pairs\n", near_looser_breaks,
              second_order_looser_breaks);
  EXPECT_EQ(pairs[kNear], 11962);
  EXPECT_EQ(pairs[kSecondOrder], 23072);
  EXPECT_EQ(worst[kNear], 1);  // the near pairs do use the one code of slack
  EXPECT_GT(near_looser_breaks, 0);
  EXPECT_GT(second_order_looser_breaks, 0);
}

// The encoder's table words (a byte and the next byte's threshold in one word per bucket) decide
// exactly at each rounding threshold: the first float of every byte, found here by bisection on
// the double-precision curve, encodes to that byte and the float below it to the byte before;
// so do the first and last floats of every bucket of the table. With the encoder monotonic
// between them, that is every float.
TEST(PixelFormats, SrgbAtEveryRoundingThreshold) {
  std::uint32_t below = float_bits(0.0f);
  for (int k = 1; k < 256; ++k) {
    std::uint32_t low = below, high = float_bits(1.0f);  // srgb_byte_double(low) < k <= ...(high)
    while (high - low > 1) {
      const std::uint32_t mid = low + (high - low) / 2;
      (srgb_byte_double(bits_float(mid)) >= k ? high : low) = mid;
    }
    ASSERT_EQ(formats::linear_to_srgb(bits_float(high)), k) << bits_float(high);
    ASSERT_EQ(formats::linear_to_srgb(bits_float(low)), k - 1) << bits_float(low);
    below = high;
  }
  for (std::uint32_t top = float_bits(1e-5f) >> 16; top <= float_bits(1.0f) >> 16; ++top) {
    for (const std::uint32_t b : {top << 16, (top << 16) | 0xffffu}) {
      if (b > float_bits(1.0f)) continue;
      ASSERT_EQ(formats::linear_to_srgb(bits_float(b)), srgb_byte_double(bits_float(b))) << bits_float(b);
    }
  }
}

// ---- frames in every format ---------------------------------------------------------------------

struct FormatCase {
  ColorFormat color;
  DepthFormat depth;
};

// A frame with walls, slopes, flat runs and far background, in float (the reference) and in
// the case's formats; the float frame holds exactly the values the formats decode to, so the
// float path sees the same scene.
struct Frames {
  int width = 0, height = 0, guard = 0;
  std::vector<float> depth_f, color_f;            // float depth; interleaved float RGBA
  std::vector<std::uint8_t> depth_b, color_b;     // the same in the case's formats (+1 byte offset)
  std::ptrdiff_t depth_stride = 0, color_stride = 0;  // bytes
  float packed_near = 0.5f, packed_far = 40.0f;
};

Frames make_frames(std::mt19937& rng, int width, int height, const FormatCase& fc, const DepthDecoder& decoder) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Frames fr;
  fr.width = width;
  fr.height = height;
  const int dbpp = bytes_per_pixel(fc.depth), cbpp = bytes_per_pixel(fc.color);
  fr.depth_stride = static_cast<std::ptrdiff_t>(width) * dbpp + 6;
  fr.color_stride = static_cast<std::ptrdiff_t>(width) * cbpp + 12;
  fr.depth_f.assign(static_cast<std::size_t>(width) * height, 0.0f);
  fr.color_f.assign(static_cast<std::size_t>(width) * height * 4, 0.0f);
  fr.depth_b.assign(static_cast<std::size_t>(fr.depth_stride) * height + 8, 0);
  fr.color_b.assign(static_cast<std::size_t>(fr.color_stride) * height + 8, 0);
  for (int y = 0; y < height; ++y) {
    int x = 0;
    while (x < width) {
      const bool flat = unit(rng) < 0.3f;
      const int length = 1 + static_cast<int>(unit(rng) * (flat ? 40.0f : 12.0f));
      const double z0 = unit(rng) < 0.2f ? 30.0 : 1.5 + 20.0 * unit(rng);
      const double slope = flat ? 0.0 : (unit(rng) - 0.5) * 0.5;
      for (int k = 0; k < length && x < width; ++k, ++x) {
        const double z = std::max(1.2, std::min(38.0, z0 + slope * k));
        std::uint8_t* word = fr.depth_b.data() + 1 + y * fr.depth_stride + static_cast<std::ptrdiff_t>(x) * dbpp;
        const std::uint32_t stencil = static_cast<std::uint32_t>(x * 7 + y) & 0xffu;
        float d = decoder.encode(z);
        switch (fc.depth) {
          case DepthFormat::float32: std::memcpy(word, &d, 4); break;
          case DepthFormat::unorm16: {
            const std::uint16_t u = static_cast<std::uint16_t>(formats::float_to_unorm(d, 16));
            std::memcpy(word, &u, 2);
            d = formats::unorm_to_float(u, 16);
            break;
          }
          case DepthFormat::unorm24_s8:
          case DepthFormat::s8_unorm24: {
            const std::uint32_t u = formats::float_to_unorm(d, 24);
            const std::uint32_t w = fc.depth == DepthFormat::unorm24_s8 ? (u | stencil << 24) : (u << 8 | stencil);
            std::memcpy(word, &w, 4);
            d = formats::unorm_to_float(u, 24);
            break;
          }
          case DepthFormat::rgba8_packed_linear: {
            // Linear depth: the decoder is linear, v spans [near, far].
            const float v = static_cast<float>((z - fr.packed_near) / (fr.packed_far - fr.packed_near));
            formats::pack_linear_value(v, word);
            word[3] = static_cast<std::uint8_t>(stencil);
            const float decoded = formats::packed_linear_value(word);
            d = decoded * (fr.packed_far - fr.packed_near) + fr.packed_near;  // (-ffp-contract=off)
            break;
          }
        }
        fr.depth_f[static_cast<std::size_t>(y) * width + x] = d;
      }
    }
    for (int x = 0; x < width; ++x) {
      std::uint8_t* px = fr.color_b.data() + 1 + y * fr.color_stride + static_cast<std::ptrdiff_t>(x) * cbpp;
      float* pf = fr.color_f.data() + (static_cast<std::size_t>(y) * width + x) * 4;
      for (int c = 0; c < 4; ++c) {
        const std::uint8_t byte = static_cast<std::uint8_t>(rng() & 0xff);
        switch (fc.color) {
          case ColorFormat::rgba8: px[c] = byte; pf[c] = byte; break;  // blended as byte values
          case ColorFormat::rgba8_srgb:
            px[c] = byte;
            pf[c] = c < 3 ? formats::srgb_to_linear(byte) : static_cast<float>(byte);
            break;
          case ColorFormat::rgba16f: {
            const std::uint16_t h = formats::float_to_half((unit(rng) - 0.2f) * 3.0f);
            std::memcpy(px + 2 * c, &h, 2);
            pf[c] = formats::half_to_float(h);
            break;
          }
          case ColorFormat::float32: pf[c] = unit(rng); std::memcpy(px + 4 * c, &pf[c], 4); break;
        }
      }
    }
  }
  return fr;
}

struct Outputs {
  std::vector<std::uint8_t> color, depth, status;
  std::vector<float> source_x;
  std::ptrdiff_t color_stride = 0, depth_stride = 0;
};

// The views of a frame in its formats (native) or as float (the float path), its outputs sized
// and pre-filled in `out`.
struct Views {
  SourceView source;
  TargetView target;
};
Views make_views(const Frames& fr, const FormatCase& fc, bool native, const Options& options, Outputs& out) {
  const int tw = fr.width - 2 * options.guard;
  const int cbpp = native ? (fc.color == ColorFormat::float32 ? 16 : bytes_per_pixel(fc.color)) : 16;
  const int dbpp = native ? bytes_per_pixel(fc.depth) : 4;
  out.color_stride = static_cast<std::ptrdiff_t>(tw) * cbpp + 20;
  out.depth_stride = static_cast<std::ptrdiff_t>(tw) * dbpp + 8;
  out.color.assign(static_cast<std::size_t>(out.color_stride) * fr.height + 4, 0xab);
  out.depth.assign(static_cast<std::size_t>(out.depth_stride) * fr.height + 4, 0xcd);
  out.status.assign(static_cast<std::size_t>(tw) * fr.height, 99);
  out.source_x.assign(static_cast<std::size_t>(tw) * fr.height, -7.0f);
  Views v;
  if (native && fc.color != ColorFormat::float32) {
    v.source.color = ColorView::packed(fc.color, fr.color_b.data() + 1, fr.width, fr.height, fr.color_stride);
    v.target.color = MutableColorView::packed(fc.color, out.color.data(), tw, fr.height, out.color_stride);
  } else {
    v.source.color = ColorView::rgba(fr.color_f.data(), fr.width, fr.height, fr.width * 4);
    v.target.color = MutableColorView::rgba(reinterpret_cast<float*>(out.color.data()), tw, fr.height, out.color_stride / 4);
  }
  if (native && fc.depth != DepthFormat::float32) {
    v.source.depth_buffer = DepthBuffer::of(fc.depth, fr.depth_b.data() + 1, fr.width, fr.height, fr.depth_stride);
    v.source.depth_buffer.linear_near = fr.packed_near;
    v.source.depth_buffer.linear_far = fr.packed_far;
    v.target.depth_buffer = MutableDepthBuffer::of(fc.depth, out.depth.data(), tw, fr.height, out.depth_stride);
  } else {
    v.source.depth = FloatPlane{fr.depth_f.data(), fr.width, fr.height, fr.width};
    v.target.depth = MutableFloatPlane{reinterpret_cast<float*>(out.depth.data()), tw, fr.height, out.depth_stride / 4};
  }
  v.target.status = BytePlane{out.status.data(), tw, fr.height, tw};
  v.target.source_x = MutableFloatPlane{out.source_x.data(), tw, fr.height, tw};
  return v;
}

// Runs the frame in its formats (native) or as float (the float path), outputs pre-filled; with
// kernels, in the sRGB lookup `srgb_lookup` when given.
Status run(const detail::KernelTable* kernels, const Frames& fr, const FormatCase& fc, bool native,
           const DepthDecoder& decoder, const ParallaxModel& model, const Options& options, Outputs& out,
           const detail::SrgbLookup* srgb_lookup = nullptr) {
  const Views v = make_views(fr, fc, native, options, out);
  if (kernels) return detail::reproject_with(*kernels, v.source, decoder, model, options, v.target, srgb_lookup);
  return reproject(v.source, decoder, model, options, v.target);
}

const FormatCase kCases[] = {
    {ColorFormat::rgba8, DepthFormat::unorm24_s8},      {ColorFormat::rgba8_srgb, DepthFormat::float32},
    {ColorFormat::rgba16f, DepthFormat::float32},       {ColorFormat::rgba8, DepthFormat::unorm16},
    {ColorFormat::rgba8_srgb, DepthFormat::s8_unorm24}, {ColorFormat::rgba16f, DepthFormat::rgba8_packed_linear},
    {ColorFormat::float32, DepthFormat::unorm16},
};

DepthDecoder decoder_for(const FormatCase& fc, int variant) {
  if (fc.depth == DepthFormat::rgba8_packed_linear || variant % 2) return DepthDecoder::linear();
  return DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 40.0);
}

Options options_for(Method method, int variant, int width) {
  Options o;
  o.method = method;
  o.guard = variant & 2 && width > 20 ? 4 : 0;
  o.hole_fill = static_cast<HoleFill>(variant % 3);
  o.edge = static_cast<EdgeMode>((variant / 2) % 4);
  if (variant % 5 == 3) o.max_negative_parallax = 2.0f;  // clipping
  o.threads = 1;
  return o;
}

ParallaxModel model_for(int variant) { return variant % 4 == 1 ? ParallaxModel{-6.0f, 40.0f} : ParallaxModel{6.0f, -40.0f}; }

class FormatsEveryArch : public ::testing::TestWithParam<Arch> {};

TEST_P(FormatsEveryArch, SimdMatchesScalarAndThreads) {
  const Arch arch = GetParam();
  if (!arch_supported(arch)) GTEST_SKIP() << not_run_reason(arch);
  const detail::KernelTable& simd = *detail::compiled_kernels(arch);
  const detail::KernelTable& reference = detail::reference_kernels(arch);
  std::mt19937 rng(static_cast<unsigned>(arch) + 101u);
  // rgba8_srgb runs with each sRGB lookup the set has (kernels/color_formats.hpp SrgbLookup:
  // AVX-512 has two, chosen at run time by speed), whichever this processor would choose.
  std::vector<detail::SrgbLookup> lookups = {detail::SrgbLookup::gathers};
  if (simd.srgb_lookup != nullptr) lookups.push_back(detail::SrgbLookup::permutes);
  long runs = 0;
  for (const FormatCase& fc : kCases) {
    for (int width : {1, 7, 16, 17, 33, 64, 129}) {
      for (int variant = 0; variant < 6; ++variant) {
        const DepthDecoder decoder = decoder_for(fc, variant);
        const Frames fr = make_frames(rng, width, 3, fc, decoder);
        for (int m = 0; m < kMethodCount; ++m) {
          const Options options = options_for(static_cast<Method>(m), variant, width);
          Outputs b;
          ASSERT_TRUE(run(&reference, fr, fc, true, decoder, model_for(variant), options, b).ok());
          for (std::size_t k = 0; k < (fc.color == ColorFormat::rgba8_srgb ? lookups.size() : 1); ++k) {
            Outputs a;
            ASSERT_TRUE(run(&simd, fr, fc, true, decoder, model_for(variant), options, a, &lookups[k]).ok());
            const auto where = [&] {
              return std::string(to_string(fc.color)) + "+" + to_string(fc.depth) + " " +
                     to_string(static_cast<Method>(m)) + " width " + std::to_string(width) + " variant " +
                     std::to_string(variant) + (lookups[k] == detail::SrgbLookup::permutes ? " (sRGB by permutes)" : "");
            };
            ASSERT_EQ(a.color, b.color) << where();
            ASSERT_EQ(a.depth, b.depth) << where();
            ASSERT_EQ(a.status, b.status) << where();
            ASSERT_EQ(0, std::memcmp(a.source_x.data(), b.source_x.data(), a.source_x.size() * 4)) << where();
            ++runs;
          }
        }
      }
    }
  }
  // Each lookup reached the resolve: the set's counting copy (tests/arch_layer/set.cpp) tells the
  // colour path of every row it resolved. Not compiled with REPROJECT_TEST_FETCH_COUNTS OFF: that
  // part alone is left out, said on the output (the rest of the test runs).
  const test::CountedTable counted = test::counted_kernels(arch);
  if (counted.table == nullptr && arch != Arch::scalar && !test::fetch_counts_compiled()) {
    std::printf("formats: %s: sRGB lookups' colour paths not counted (built with "
                "REPROJECT_TEST_FETCH_COUNTS=OFF)\n", to_string(arch));
  }
  if (counted.table != nullptr) {
    const FormatCase fc{ColorFormat::rgba8_srgb, DepthFormat::float32};
    const DepthDecoder decoder = decoder_for(fc, 0);
    const Frames fr = make_frames(rng, 97, 5, fc, decoder);
    for (detail::SrgbLookup lookup : lookups) {
      const test::FetchModeCounts before = *counted.of_thread();
      Outputs a;
      ASSERT_TRUE(run(counted.table, fr, fc, true, decoder, model_for(0), options_for(Method::single, 0, 97), a, &lookup).ok());
      const test::FetchModeCounts& after = *counted.of_thread();
      const bool permutes = lookup == detail::SrgbLookup::permutes;
      const int path = permutes ? test::kPathSrgbByPermutes : test::kPathSrgbByGathers;
      const int other = permutes ? test::kPathSrgbByGathers : test::kPathSrgbByPermutes;
      EXPECT_EQ(after.rows_by_path[path] - before.rows_by_path[path], 5u) << (permutes ? "permutes" : "gathers");
      EXPECT_EQ(after.rows_by_path[other], before.rows_by_path[other]) << (permutes ? "permutes" : "gathers");
    }
  }
  // 1 thread = 2 threads, through the public entry point, on a frame tall enough to split.
  for (const FormatCase& fc : kCases) {
    const DepthDecoder decoder = decoder_for(fc, 0);
    const Frames fr = make_frames(rng, 97, 40, fc, decoder);
    for (int m = 0; m < kMethodCount; ++m) {
      Options options = options_for(static_cast<Method>(m), 0, 97);
      options.arch = arch;
      Outputs one, two;
      ASSERT_TRUE(run(nullptr, fr, fc, true, decoder, model_for(0), options, one).ok());
      options.threads = 2;
      ASSERT_TRUE(run(nullptr, fr, fc, true, decoder, model_for(0), options, two).ok());
      ASSERT_EQ(one.color, two.color);
      ASSERT_EQ(one.depth, two.depth);
      ASSERT_EQ(one.status, two.status);
    }
  }
  std::printf("formats: %s: %ld runs bit-identical to the scalar reference\n", to_string(arch), runs);
}

INSTANTIATE_TEST_SUITE_P(EveryArch, FormatsEveryArch, ::testing::ValuesIn(every_arch()),
                         [](const ::testing::TestParamInfo<Arch>& info) { return std::string(to_string(info.param)); });

// How each set reads the sRGB tables (kernels/dispatch.hpp srgb_lookup_for): AVX-512 has two
// ways, timed once per process unless REPROJECT_SRGB_LOOKUP names one (ctest SrgbLookup.* runs
// this test with each value), every other set one (gathers). The choice holds for the process.
TEST(PixelFormats, SrgbLookupChoice) {
  const char* env = std::getenv("REPROJECT_SRGB_LOOKUP");
  const std::string named = env ? env : "";
  int checked = 0;
  for (int a = 0; a < kArchCount; ++a) {
    const Arch arch = static_cast<Arch>(a);
    if (!arch_supported(arch)) continue;
    const detail::KernelTable& kernels = *detail::compiled_kernels(arch);
    ++checked;
    if (arch != Arch::avx512) {
      EXPECT_EQ(kernels.srgb_lookup, nullptr) << to_string(arch);
      EXPECT_EQ(detail::srgb_lookup_for(kernels), detail::SrgbLookup::gathers) << to_string(arch);
      continue;
    }
    ASSERT_NE(kernels.srgb_lookup, nullptr) << "the AVX-512 table has two sRGB lookups";
    const detail::SrgbLookup chosen = detail::srgb_lookup_for(kernels);
    EXPECT_EQ(detail::srgb_lookup_for(kernels), chosen) << "chosen once per process";
    if (named == "gathers" || named == "permutes") {
      EXPECT_EQ(chosen, named == "permutes" ? detail::SrgbLookup::permutes : detail::SrgbLookup::gathers);
    } else {  // timed: the table's own answer
      EXPECT_EQ(chosen, kernels.srgb_lookup());
    }
    std::printf("[ sRGB     ] avx512 reads the sRGB tables by %s (%s)\n",
                chosen == detail::SrgbLookup::permutes ? "permutes" : "gathers",
                named == "gathers" || named == "permutes" ? ("REPROJECT_SRGB_LOOKUP=" + named).c_str()
                                                          : "timed on this processor");
  }
  EXPECT_GT(checked, 0);
}

// The native formats against the float path on the same frame (the float frame holds the values
// the formats decode to): the search sees the same parallax, so status and source x are
// identical; colour and depth differ only by the formats' rounding.
TEST(PixelFormats, NativeMatchesTheFloatPath) {
  std::mt19937 rng(77);
  long pixels = 0, color_off = 0, depth_off = 0;
  for (const FormatCase& fc : kCases) {
    for (int variant = 0; variant < 6; ++variant) {
      const DepthDecoder decoder = decoder_for(fc, variant);
      const Frames fr = make_frames(rng, 150, 6, fc, decoder);
      for (int m = 0; m < kMethodCount; ++m) {
        Options options = options_for(static_cast<Method>(m), variant, 150);
        options.edge = options.edge == EdgeMode::none ? EdgeMode::clamp : options.edge;  // every pixel written
        options.hole_fill = options.hole_fill == HoleFill::none ? HoleFill::background : options.hole_fill;
        Outputs native, floats;
        ASSERT_TRUE(run(nullptr, fr, fc, true, decoder, model_for(variant), options, native).ok());
        ASSERT_TRUE(run(nullptr, fr, fc, false, decoder, model_for(variant), options, floats).ok());
        ASSERT_EQ(native.status, floats.status) << to_string(fc.color) << "+" << to_string(fc.depth) << " method " << m;
        ASSERT_EQ(0, std::memcmp(native.source_x.data(), floats.source_x.data(), native.source_x.size() * 4));
        const int tw = 150 - 2 * options.guard;
        for (int y = 0; y < 6; ++y) {
          for (int t = 0; t < tw; ++t) {
            const float* f = reinterpret_cast<const float*>(floats.color.data() + y * floats.color_stride) + 4 * t;
            const std::uint8_t* n = native.color.data() + y * native.color_stride;
            for (int c = 0; c < 4; ++c) {
              int diff = 0;
              switch (fc.color) {
                case ColorFormat::rgba8: diff = std::abs(n[4 * t + c] - static_cast<int>(std::lround(f[c]))); break;
                case ColorFormat::rgba8_srgb:
                  diff = std::abs(n[4 * t + c] - (c < 3 ? formats::linear_to_srgb(f[c]) : static_cast<int>(std::lround(f[c]))));
                  break;
                case ColorFormat::rgba16f: {  // the same blend, rounded once to half: equal
                  std::uint16_t h;
                  std::memcpy(&h, n + 8 * t + 2 * c, 2);
                  diff = h != formats::float_to_half(f[c]) ? 2 : 0;
                  break;
                }
                case ColorFormat::float32: diff = std::memcmp(n + 16 * t + 4 * c, f + c, 4) != 0 ? 2 : 0; break;
              }
              ASSERT_LE(diff, 1) << to_string(fc.color) << " method " << m << " pixel " << t << " channel " << c;
              color_off += diff != 0;
            }
            const float fd = reinterpret_cast<const float*>(floats.depth.data() + y * floats.depth_stride)[t];
            const std::uint8_t* nd = native.depth.data() + y * native.depth_stride;
            long code = 0, expected = 0;
            switch (fc.depth) {
              case DepthFormat::float32: code = float_bits(reinterpret_cast<const float*>(nd)[t]); expected = float_bits(fd); break;
              case DepthFormat::unorm16: {
                std::uint16_t u;
                std::memcpy(&u, nd + 2 * t, 2);
                code = u;
                expected = formats::float_to_unorm(fd, 16);
                break;
              }
              case DepthFormat::unorm24_s8:
              case DepthFormat::s8_unorm24: {
                std::uint32_t w;
                std::memcpy(&w, nd + 4 * t, 4);
                code = fc.depth == DepthFormat::unorm24_s8 ? (w & 0xffffff) : (w >> 8);
                expected = formats::float_to_unorm(fd, 24);
                break;
              }
              case DepthFormat::rgba8_packed_linear: {
                code = std::lround(static_cast<double>(formats::packed_linear_value(nd + 4 * t)) * 16581375.0);
                expected = std::lround((fd - fr.packed_near) / (fr.packed_far - fr.packed_near) * 16581375.0);
                break;
              }
            }
            ASSERT_LE(std::labs(code - expected), 1) << to_string(fc.depth) << " method " << m << " pixel " << t;
            depth_off += code != expected;
            ++pixels;
          }
        }
      }
    }
  }
  std::printf("native vs float path: %ld pixels, identical status and x; %ld channels and %ld depths one LSB off\n",
              pixels, color_off, depth_off);
}

// reproject_pair on every format: each eye equals its own reproject() call (the pair shares the
// decode, and D16's kept stored values, between the eyes).
TEST(PixelFormats, PairEqualsTwoSingleCalls) {
  std::mt19937 rng(91);
  long compared = 0;
  for (const FormatCase& fc : kCases) {
    const DepthDecoder decoder = decoder_for(fc, 0);
    const Frames fr = make_frames(rng, 75, 9, fc, decoder);
    for (int m = 0; m < kMethodCount; ++m) {
      for (int variant : {0, 3}) {
        const Options options = options_for(static_cast<Method>(m), variant, 75);
        const ParallaxModel right{4.0f, -35.0f};
        Outputs single[2], pair[2];
        ASSERT_TRUE(run(nullptr, fr, fc, true, decoder, ParallaxModel{-right.a, -right.b}, options, single[0]).ok());
        ASSERT_TRUE(run(nullptr, fr, fc, true, decoder, right, options, single[1]).ok());
        // The pair: the same views as run() builds, with both targets.
        const Views left = make_views(fr, fc, true, options, pair[0]);
        const Views right_views = make_views(fr, fc, true, options, pair[1]);
        ASSERT_TRUE(reproject_pair(left.source, decoder, right, options, left.target, right_views.target).ok());
        for (int eye = 0; eye < 2; ++eye) {
          ASSERT_EQ(pair[eye].color, single[eye].color) << to_string(fc.color) << "+" << to_string(fc.depth) << " eye " << eye;
          ASSERT_EQ(pair[eye].depth, single[eye].depth) << to_string(fc.color) << "+" << to_string(fc.depth) << " eye " << eye;
          ASSERT_EQ(pair[eye].status, single[eye].status);
          ASSERT_EQ(0, std::memcmp(pair[eye].source_x.data(), single[eye].source_x.data(), single[eye].source_x.size() * 4));
          ++compared;
        }
      }
    }
  }
  std::printf("formats: %ld pair eyes equal their single calls\n", compared);
}

TEST(PixelFormats, ClearErrors) {
  std::vector<std::uint8_t> bytes(64 * 4 * 8), out(64 * 4 * 8);
  std::vector<float> depth(64 * 8);
  SourceView source;
  source.color = ColorView::packed(ColorFormat::rgba8, bytes.data(), 64, 8, 64 * 4);
  source.depth = FloatPlane{depth.data(), 64, 8, 64};
  TargetView target;
  target.color = MutableColorView::packed(ColorFormat::rgba8_srgb, out.data(), 64, 8, 64 * 4);
  const DepthDecoder decoder = DepthDecoder::linear();
  Status s = reproject(source, decoder, ParallaxModel{1.0f, -1.0f}, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::size_mismatch);
  EXPECT_NE(std::string(s.message()).find("rgba8_srgb"), std::string::npos) << s.message();
  target.color.format = ColorFormat::rgba8;
  target.color.pixels.stride = 100;  // < 64 * 4 bytes
  s = reproject(source, decoder, ParallaxModel{1.0f, -1.0f}, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::invalid_stride) << s.message();
  target.color.pixels.stride = 256;
  source.depth_buffer = DepthBuffer::of(DepthFormat::unorm16, bytes.data(), 64, 8, 128);
  s = reproject(source, decoder, ParallaxModel{1.0f, -1.0f}, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::invalid_option) << s.message();  // both depths set
  source.depth = FloatPlane{};
  target.depth = MutableFloatPlane{depth.data(), 64, 8, 64};
  s = reproject(source, decoder, ParallaxModel{1.0f, -1.0f}, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::size_mismatch) << s.message();  // float output for D16 input
  target.depth = MutableFloatPlane{};
  source.depth_buffer.format = static_cast<DepthFormat>(9);
  s = reproject(source, decoder, ParallaxModel{1.0f, -1.0f}, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::invalid_option) << s.message();
  source.depth_buffer = DepthBuffer::packed_linear(bytes.data(), 64, 8, 256, 2.0f, 2.0f);
  s = reproject(source, decoder, ParallaxModel{1.0f, -1.0f}, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::invalid_option) << s.message();
  source.depth_buffer = DepthBuffer::of(DepthFormat::unorm16, bytes.data() + 2, 64, 8, 128);  // overlaps colour
  s = reproject(source, decoder, ParallaxModel{1.0f, -1.0f}, Options(), target);
  EXPECT_TRUE(s.ok()) << s.message();  // inputs may overlap each other
  target.depth_buffer = MutableDepthBuffer::of(DepthFormat::unorm16, bytes.data(), 64, 8, 128);  // an input
  s = reproject(source, decoder, ParallaxModel{1.0f, -1.0f}, Options(), target);
  EXPECT_EQ(s.code(), StatusCode::aliasing) << s.message();
}

}  // namespace
}  // namespace reproject
