// SIMD twins against their scalar references: bit-identical outputs (colour, depth, status,
// source x) for every method x compiled instruction set x decoder shape x colour layout x fill
// and edge mode, over awkward widths, odd strides and misaligned base pointers. Instruction sets
// the CPU lacks are skipped (and reported).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "kernels/codes.hpp"
#include "kernels/depth_formats.hpp"
#include "kernels/dispatch.hpp"
#include "kernels/frame.hpp"
#include "src/reproject_internal.hpp"
#include "reproject/reproject.hpp"
#include "support/arch_report.hpp"
#include "tests/arch_layer/sets.hpp"

namespace reproject {
namespace {

struct Case {
  int width;   // source width
  int guard;
  bool interleaved;
  bool reciprocal;  // linear depth (w = 1/d) instead of the affine standard encoding
  bool clip;        // a near limit tighter than the data
  bool mirrored;    // b > 0 (right to left)
};

// A frame with walls, folds, slopes, far background, a few non-finite depths, stored with one
// float of misalignment and an odd stride.
struct Frame {
  int width, height;
  std::ptrdiff_t stride;
  std::vector<float> depth, color;
};

// A signalling NaN of either sign with a payload that varies with k: the kernels carry it (quieted)
// exactly as their scalar references do.
float signalling_nan(unsigned k) {
  return detail::float_of_bits((k % 2 ? 0xff800000u : 0x7f800000u) | (1u + (k * 2654435761u) % 0x3fffffu));
}

Frame make_frame(std::mt19937& rng, const Case& c, const DepthDecoder& decoder) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Frame frame;
  frame.width = c.width;
  frame.height = 5;
  frame.stride = static_cast<std::ptrdiff_t>(c.width) * (c.interleaved ? 4 : 1) + 3;  // odd
  frame.depth.assign(1 + frame.stride * frame.height, 0.0f);
  const int channels = c.interleaved ? 1 : 3;
  frame.color.assign(1 + frame.stride * frame.height * channels, 0.0f);
  for (int y = 0; y < frame.height; ++y) {
    int x = 0;
    while (x < c.width) {
      // Some runs long and flat (constant parallax: the resolve's plain-load fetch), most short.
      const bool flat = unit(rng) < 0.25f;
      const int length = 1 + static_cast<int>(unit(rng) * (flat ? 40.0f : 12.0f));
      const double z0 = unit(rng) < 0.2f ? 19.0 : 1.2 + 15.0 * unit(rng);
      const double slope = flat ? 0.0 : (unit(rng) - 0.5) * 0.4;
      for (int k = 0; k < length && x < c.width; ++k, ++x) {
        float d = decoder.encode(std::max(1.05, z0 + slope * k));
        const float roll = unit(rng);
        float* stored = &frame.depth[1 + y * frame.stride + x];
        if (roll < 0.01f) {
          d = roll < 0.005f ? std::numeric_limits<float>::quiet_NaN() : signalling_nan(static_cast<unsigned>(y * c.width + x));
          // Two different NaNs side by side would make an interpolation between them pick one,
          // and which one is not specified (docs/BEHAVIOUR.md, "NaNs"): a NaN next to a NaN repeats it.
          if (x > 0 && std::isnan(stored[-1])) d = stored[-1];
        } else if (roll < 0.015f) {
          d = std::numeric_limits<float>::infinity();
        } else if (roll < 0.02f) {
          d = -1.0f;
        }
        *stored = d;
      }
    }
  }
  for (float& v : frame.color) v = unit(rng);
  return frame;
}

struct Out {
  std::vector<float> color, depth, source_x;
  std::vector<std::uint8_t> status;
};

Status run(const detail::KernelTable& kernels, const Frame& frame, const Case& c, const DepthDecoder& decoder,
           const ParallaxModel& model, const Options& options, Out& out) {
  const int tw = frame.width - 2 * c.guard;
  const std::ptrdiff_t ts = static_cast<std::ptrdiff_t>(tw) * (c.interleaved ? 4 : 1) + 5;  // odd
  const int channels = c.interleaved ? 1 : 3;
  // Pre-filled with a sentinel, so unwritten pixels (fill none, edge none) compare too.
  out.color.assign(1 + ts * frame.height * channels, -7.0f);
  out.depth.assign(1 + ts * frame.height, -7.0f);
  out.source_x.assign(1 + ts * frame.height, -7.0f);
  out.status.assign(1 + ts * frame.height, 99);
  SourceView source;
  TargetView target;
  const std::ptrdiff_t plane = frame.stride * frame.height;
  const std::ptrdiff_t tplane = ts * frame.height;
  if (c.interleaved) {
    source.color = ColorView::rgba(frame.color.data() + 1, frame.width, frame.height, frame.stride);
    target.color = MutableColorView::rgba(out.color.data() + 1, tw, frame.height, ts);
  } else {
    for (int ch = 0; ch < 3; ++ch) {
      source.color.plane[ch] = FloatPlane{frame.color.data() + 1 + ch * plane, frame.width, frame.height, frame.stride};
      target.color.plane[ch] = MutableFloatPlane{out.color.data() + 1 + ch * tplane, tw, frame.height, ts};
    }
    source.color.channels = target.color.channels = 3;
  }
  source.depth = FloatPlane{frame.depth.data() + 1, frame.width, frame.height, frame.stride};
  target.depth = MutableFloatPlane{out.depth.data() + 1, tw, frame.height, ts};
  target.status = BytePlane{out.status.data() + 1, tw, frame.height, ts};
  target.source_x = MutableFloatPlane{out.source_x.data() + 1, tw, frame.height, ts};
  return detail::reproject_with(kernels, source, decoder, model, options, target);
}

bool same_bits(const std::vector<float>& x, const std::vector<float>& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
}

class SimdMatchesScalar : public ::testing::TestWithParam<Arch> {};

TEST_P(SimdMatchesScalar, BitIdenticalEverywhere) {
  const Arch arch = GetParam();
  if (!arch_supported(arch)) GTEST_SKIP() << not_run_reason(arch);
  const detail::KernelTable& simd = *detail::compiled_kernels(arch);
  const detail::KernelTable& reference = detail::reference_kernels(arch);
#if defined(__GNUC__)  // GCC and Clang builds compile the AVX2 + FMA copy of the scalar references
  if (arch == Arch::scalar && arch_supported(Arch::avx2)) {
    ASSERT_NE(&simd, &reference) << "Arch::scalar should run the AVX2 + FMA build of the references here";
  }
#endif
  std::mt19937 rng(static_cast<unsigned>(arch) * 7919u + 17u);
  const int L = 16;  // the widest vector: covers every narrower one's tails too
  // Awkward widths, and the vector body / scalar tail boundary on every lane count (4, 8, 16)
  // and one either side of it; and rows of two and three of march16's resolve chunks, the last
  // partial (kernels/march16_simd.hpp kMarchResolveChunk, 1024 target pixels).
  const int widths[] = {1, 3, 4, 5, 7, 8, 9, L - 1, L, L + 1, 31, 32, 33, 63, 64, 65, 5 * L + 3, 127, 128, 129, 131,
                        1024 + 5 * L + 3, 2 * 1024 + 2 * L + 1};
  long runs = 0, mismatched = 0;
  // The same set's table built once more with a tally of the resolve's column-fetch modes
  // (tests/arch_layer/set.cpp; the library's tables count nothing): it runs every case too, must
  // give the same bits, and its counts show that every mode ran (the runs use one thread). A build
  // configured with REPROJECT_TEST_FETCH_COUNTS=OFF has no such copy: the comparisons with the
  // scalar reference run all the same, and only the counts are not checked.
  const test::CountedTable counted = test::counted_kernels(arch);
  const test::FetchModeCounts* modes = counted.table ? counted.of_thread() : nullptr;
  const test::FetchModeCounts modes_before = modes ? *modes : test::FetchModeCounts{};
  if (arch != Arch::scalar && test::fetch_counts_compiled()) {
    ASSERT_NE(counted.table, nullptr) << "no counting copy of the " << to_string(arch) << " table";
  }
  for (int width : widths) {
    for (int variant = 0; variant < 8; ++variant) {
      Case c;
      c.width = width;
      c.guard = (variant & 4) && width >= 9 ? 3 : 0;
      c.interleaved = variant & 1;
      c.reciprocal = variant & 2;
      c.clip = variant % 3 == 1;
      c.mirrored = variant % 3 == 2;
      const DepthDecoder decoder = c.reciprocal ? DepthDecoder::linear()
                                                : DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 20.0);
      const Frame frame = make_frame(rng, c, decoder);
      const int tw = width - 2 * c.guard;
      const ParallaxModel model = ParallaxModel::from_stereo(
          0.03 + 0.1 * (variant % 2), 4.0, std::max(tw, 40), c.mirrored ? EyeDirection::right_to_left : EyeDirection::left_to_right);
      for (int m = 0; m < kMethodCount; ++m) {
        for (HoleFill fill : {HoleFill::background, HoleFill::foreground, HoleFill::none}) {
          for (EdgeMode edge : {EdgeMode::clamp, EdgeMode::none, EdgeMode::black, EdgeMode::mirror}) {
            Options options;
            options.method = static_cast<Method>(m);
            options.guard = c.guard;
            options.hole_fill = fill;
            options.edge = edge;
            options.threads = 1;  // the fetch-mode counts are the calling thread's
            if (c.clip) options.max_negative_parallax = 1.5f;
            if (m == static_cast<int>(Method::secant) && variant % 2 == 1) options.secant_max_steps = 3;  // coarse steps + refinement
            // march16's rows of 1 to 17 deciding samples run unrolled, longer ones in chunks of 16:
            // one step (two samples), the default 16, and 40 (rows of more than 17 samples: chunks).
            if (m == static_cast<int>(Method::march16) && variant % 4 == 1) options.march_steps = 40;
            if (m == static_cast<int>(Method::march16) && variant % 4 == 3) options.march_steps = 1;
            Out expected, got, got_counted;
            ASSERT_TRUE(run(reference, frame, c, decoder, model, options, expected).ok());
            ASSERT_TRUE(run(simd, frame, c, decoder, model, options, got).ok());
            if (counted.table) {
              ASSERT_TRUE(run(*counted.table, frame, c, decoder, model, options, got_counted).ok());
            }
            ++runs;
            auto same_as_expected = [&](const Out& o) {
              return same_bits(expected.color, o.color) && same_bits(expected.depth, o.depth) &&
                     same_bits(expected.source_x, o.source_x) && expected.status == o.status;
            };
            const bool same = same_as_expected(got) && (!counted.table || same_as_expected(got_counted));
            if (!same) {
              ++mismatched;
              ADD_FAILURE() << to_string(arch) << " differs from its scalar reference: method "
                            << to_string(options.method) << ", width " << width << ", variant " << variant
                            << ", fill " << static_cast<int>(fill) << ", edge " << static_cast<int>(edge);
            }
          }
        }
      }
    }
  }
  std::printf("%s: %ld runs, %ld differ from the scalar reference\n", to_string(arch), runs, mismatched);
  EXPECT_EQ(mismatched, 0);
  if (modes) {
    // Every fetch mode ran: plain loads, one permute, two-register permute (AVX2, AVX-512, and
    // NEON with its byte table look-ups), gathers. SSE4.1 has no variable permute: it gathers.
    const char* names[4] = {"consecutive", "shifted", "spanning", "gather"};
    const bool permutes = arch == Arch::avx2 || arch == Arch::avx512 || arch == Arch::neon;
    std::printf("%s: resolve vectors by fetch mode:", to_string(arch));
    for (int m = 0; m < 4; ++m) {
      const std::uint64_t n = modes->vectors[m] - modes_before.vectors[m];
      std::printf(" %s %llu", names[m], static_cast<unsigned long long>(n));
      if (permutes || m == 3) EXPECT_GT(n, 0u) << to_string(arch) << " never used the " << names[m] << " fetch";
      else EXPECT_EQ(n, 0u) << to_string(arch) << " has no permute, yet used the " << names[m] << " fetch";
    }
    std::printf("\n");
  } else if (arch != Arch::scalar) {
    // Said on the test's output, not as a skip: the bit-identity checks above ran all the same.
    std::printf("%s: fetch modes not counted (built with REPROJECT_TEST_FETCH_COUNTS=OFF)\n",
                to_string(arch));
  }
}

// Arch::scalar: the scalar references built with AVX2 + FMA flags (what Arch::scalar runs on such
// CPUs) against the baseline build, which every other table is held to.
INSTANTIATE_TEST_SUITE_P(EveryArch, SimdMatchesScalar,
                         ::testing::ValuesIn(every_arch()),
                         [](const ::testing::TestParamInfo<Arch>& info) { return std::string(to_string(info.param)); });

// `exact` with a near limit on rows where what is nearer than the limit is a band or two (objects
// in front of a background), as an engine's fixed limit leaves it: the SIMD sweep paints whole
// vectors before and after the band's columns and masks inside them (kernels/exact_simd.hpp,
// exact_paint_clipping), and skips the ray-start test away from them. Every placement of the
// band (at either edge, in the middle, two bands), slanted objects that cross the limit, folds and
// holes at their edges, both eye directions, against the scalar reference.
class ExactNearBands : public ::testing::TestWithParam<Arch> {};

TEST_P(ExactNearBands, BitIdenticalAroundTheBands) {
  const Arch arch = GetParam();
  if (!arch_supported(arch)) GTEST_SKIP() << not_run_reason(arch);
  const detail::KernelTable& simd = *detail::compiled_kernels(arch);
  const detail::KernelTable& reference = detail::reference_kernels(arch);
  std::mt19937 rng(977u + static_cast<unsigned>(arch));
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const int widths[] = {17, 40, 97, 256, 701};
  long runs = 0, mismatched = 0, clipped_pixels = 0;
  for (int trial = 0; trial < 240; ++trial) {
    Case c{};
    c.width = widths[trial % 5];
    c.guard = trial % 3 == 0 && c.width > 20 ? 3 : 0;
    c.mirrored = (trial / 5) % 2 == 1;
    c.clip = true;
    Frame frame;
    frame.width = c.width;
    frame.height = 3;
    frame.stride = c.width + 3;
    frame.depth.assign(1 + frame.stride * frame.height, 0.0f);
    frame.color.assign(1 + frame.stride * frame.height * 3, 0.0f);
    for (float& v : frame.color) v = unit(rng);
    for (int y = 0; y < frame.height; ++y) {
      float* w = frame.depth.data() + 1 + y * frame.stride;
      // Disparity: a far background, gently sloped, then objects nearer than it.
      const float slope = (unit(rng) - 0.5f) * 0.004f;
      for (int x = 0; x < c.width; ++x) w[x] = 0.1f + 0.02f * unit(rng) + slope * static_cast<float>(x);
      const int objects = 1 + static_cast<int>(unit(rng) * 2.0f);
      for (int o = 0; o < objects; ++o) {
        // Wide objects, or poles of a few columns far nearer than the limit (whose rays start
        // behind the background beside them, so what the sweep left there shows).
        const bool pole = unit(rng) < 0.5f;
        const int length = 1 + static_cast<int>(unit(rng) * static_cast<float>(pole ? 4 : std::min(c.width, 60)));
        const int kind = static_cast<int>(unit(rng) * 4.0f);  // anywhere, at the left edge, at the right edge
        const int start = kind == 1 ? 0 : kind == 2 ? c.width - length : static_cast<int>(unit(rng) * static_cast<float>(c.width - length));
        const float w0 = pole ? 1.0f + 1.5f * unit(rng) : 0.6f + 0.6f * unit(rng), tilt = (unit(rng) - 0.5f) * 0.04f;
        for (int k = 0; k < length; ++k) w[start + k] = w0 + tilt * static_cast<float>(k);
      }
    }
    const float magnitude = 8.0f + 24.0f * unit(rng);
    const ParallaxModel model{(unit(rng) - 0.5f) * 10.0f, c.mirrored ? magnitude : -magnitude};
    const float s = model.b > 0.0f ? 1.0f : -1.0f;
    for (HoleFill fill : {HoleFill::background, HoleFill::none}) {
      Options options;
      options.method = Method::exact;
      options.guard = c.guard;
      options.hole_fill = fill;
      options.threads = 1;
      // The limit's key s a + |b| w_cut: surfaces with w above w_cut are too near.
      options.max_negative_parallax = s * model.a + magnitude * (0.55f + 0.6f * unit(rng));
      Out expected, got;
      ASSERT_TRUE(run(reference, frame, c, DepthDecoder::disparity(), model, options, expected).ok());
      ASSERT_TRUE(run(simd, frame, c, DepthDecoder::disparity(), model, options, got).ok());
      ++runs;
      clipped_pixels += std::count(expected.status.begin(), expected.status.end(),
                                   static_cast<std::uint8_t>(PixelStatus::clipped));
      if (!(same_bits(expected.color, got.color) && same_bits(expected.depth, got.depth) &&
            same_bits(expected.source_x, got.source_x) && expected.status == got.status)) {
        ++mismatched;
        ADD_FAILURE() << to_string(arch) << " differs from its scalar reference: trial " << trial << ", width " << c.width;
      }
    }
  }
  std::printf("%s: %ld exact runs with near bands, %ld clipped pixels, %ld differ\n", to_string(arch), runs,
              clipped_pixels, mismatched);
  EXPECT_GT(clipped_pixels, 1000);  // the limit did cut into the objects
  EXPECT_EQ(mismatched, 0);
}

INSTANTIATE_TEST_SUITE_P(EveryArch, ExactNearBands, ::testing::ValuesIn(every_arch()),
                         [](const ::testing::TestParamInfo<Arch>& info) { return std::string(to_string(info.param)); });

// reproject_pair decodes each row once, for the right eye, and gives the left eye (the mirror
// model) 0 - p: that must be the left eye's own decode bit for bit, zeros and clamps included,
// on every arch, for both decoder shapes and awkward models (a = +-0, huge b).
TEST(PairDecode, LeftEyeIsTheNegatedRightEyeBitForBit) {
  const float specials[] = {0.0f, -0.0f, 1.0f, 0.5f, 1e-30f, -1.0f, 1e30f, std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::denorm_min(), 0.999999f, 3.0e-8f};
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> depth;
  for (float v : specials) depth.push_back(v);
  while (depth.size() < 200) depth.push_back(unit(rng) < 0.1f ? specials[rng() % 13] : unit(rng) * 2.0f);
  const int width = static_cast<int>(depth.size());
  std::vector<float> color(depth.size(), 0.5f), out(depth.size());
  long compared = 0;
  for (const DepthDecoder& decoder : {DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 20.0), DepthDecoder::linear(),
                                      DepthDecoder::from_near_far(DepthEncoding::reversed, 0.1, 100.0)}) {
    for (const ParallaxModel right : {ParallaxModel{28.8f, -100.8f}, ParallaxModel{0.0f, -3.0f}, ParallaxModel{-0.0f, -1.0f},
                                      ParallaxModel{5.0f, -1e30f}, ParallaxModel{-12.0f, 40.0f}}) {
      // (b = +-0 is not mirrored in the plan: both eyes get s = -1, and each decodes itself;
      // Threads and fuzz_reproject compare such pairs with single calls.)
      const ParallaxModel left{-right.a, -right.b};
      SourceView source;
      // plan_frame takes the normalised views of src/validate.hpp: depth as a depth buffer.
      source.depth_buffer = DepthBuffer::of(DepthFormat::float32, depth.data(), width, 1, width * 4);
      source.color = ColorView::planar({FloatPlane{color.data(), width, 1, width}});
      TargetView target;
      target.color = MutableColorView::planar({MutableFloatPlane{out.data(), width, 1, width}});
      for (int a = 0; a < kArchCount; ++a) {
        if (!arch_supported(static_cast<Arch>(a))) continue;
        const detail::KernelTable& kernels = *detail::compiled_kernels(static_cast<Arch>(a));
        const detail::Frame fr = detail::plan_frame(source, decoder, right, Options(), target);
        const detail::Frame fl = detail::plan_frame(source, decoder, left, Options(), target);
        std::vector<float> pr(depth.size()), pl(depth.size());
        const auto* depth_bytes = reinterpret_cast<const std::uint8_t*>(depth.data());
        kernels.decode(fr, depth_bytes, pr.data(), nullptr);
        kernels.decode(fl, depth_bytes, pl.data(), nullptr);
        for (int i = 0; i < width; ++i) {
          const float negated = 0.0f - pr[static_cast<std::size_t>(i)];
          ++compared;
          ASSERT_EQ(std::memcmp(&negated, &pl[static_cast<std::size_t>(i)], sizeof(float)), 0)
              << to_string(static_cast<Arch>(a)) << " column " << i << " depth " << depth[static_cast<std::size_t>(i)]
              << ": left " << pl[static_cast<std::size_t>(i)] << ", 0 - right " << negated << " (a " << right.a
              << ", b " << right.b << ")";
        }
      }
    }
  }
  std::printf("pair decode: %ld columns compared, left == 0 - right everywhere\n", compared);
}

// The near pass over a UNORM depth row reduces codes and decodes only the lowest and the highest
// (kernels/decode_simd.hpp, near_pass_by_codes): it must give the key of the full decode, bit for
// bit (up to the sign of a zero, which set_near_key makes +0), on every arch, for every encoding
// (both directions of the key in the code), both decode shapes, awkward models (b = +-0, huge b,
// both signs of s), codes 0 and max, and rows whose nearest key is at either end.
TEST(NearPass, UnormCodesGiveTheKeyOfTheFullDecode) {
  std::mt19937 rng(11);
  std::vector<DepthDecoder> decoders = {DepthDecoder::linear(), DepthDecoder::disparity()};
  for (int e = 0; e < kDepthEncodingCount; ++e) {
    const auto encoding = static_cast<DepthEncoding>(e);
    if (encoding != DepthEncoding::linear && encoding != DepthEncoding::disparity) {
      decoders.push_back(DepthDecoder::from_near_far(encoding, 0.5, 40.0));
    }
  }
  const ParallaxModel models[] = {{28.8f, -100.8f}, {-12.0f, 40.0f}, {0.0f, -0.0f}, {3.0f, 0.0f}, {5.0f, -1e30f}, {-0.0f, 1e-3f}};
  long rows = 0, low_end = 0, high_end = 0, by_codes = 0;
  for (DepthFormat format : {DepthFormat::unorm16, DepthFormat::unorm24_s8, DepthFormat::s8_unorm24}) {
    const bool u16 = format == DepthFormat::unorm16;
    const std::uint32_t max_code = u16 ? 0xffffu : 0xffffffu;
    for (const DepthDecoder& decoder : decoders) {
      for (const ParallaxModel& model : models) {
        for (int trial = 0; trial < 6; ++trial) {
          const int width = 1 + static_cast<int>(rng() % 80);
          // Codes over the whole range, or bunched (a narrow band, where neighbouring codes can
          // round to one key), with the ends 0 and max sometimes in; random stencil bits.
          const std::uint32_t centre = rng() % (max_code + 1), spread = trial % 2 ? 40u : max_code;
          std::vector<std::uint32_t> codes(static_cast<std::size_t>(width));
          for (auto& code : codes) {
            const std::uint32_t r = rng() % 16;
            code = r == 0 ? 0u : r == 1 ? max_code : std::min<std::uint32_t>(max_code, centre + rng() % (spread + 1));
          }
          std::vector<std::uint8_t> row(static_cast<std::size_t>(width) * 4);
          for (int i = 0; i < width; ++i) {
            const std::uint32_t stencil = rng() & 0xffu, code = codes[static_cast<std::size_t>(i)];
            if (u16) {
              const std::uint16_t half = static_cast<std::uint16_t>(code);
              std::memcpy(row.data() + 2 * i, &half, 2);
            } else {
              const std::uint32_t word = format == DepthFormat::unorm24_s8 ? code | stencil << 24 : code << 8 | stencil;
              std::memcpy(row.data() + 4 * i, &word, 4);
            }
          }
          std::vector<float> color(static_cast<std::size_t>(width), 0.5f), out(color.size());
          SourceView source;
          source.depth_buffer = DepthBuffer::of(format, row.data(), width, 1, width * (u16 ? 2 : 4));
          source.color = ColorView::planar({FloatPlane{color.data(), width, 1, width}});
          TargetView target;
          target.color = MutableColorView::planar({MutableFloatPlane{out.data(), width, 1, width}});
          const detail::Frame frame = detail::plan_frame(source, decoder, model, Options(), target);
          by_codes += detail::near_pass_by_codes(frame);
          // Where the row's nearest key lies: at its lowest code, its highest, or both.
          const detail::KernelTable& scalar = detail::reference_kernels(Arch::scalar);
          const float whole = scalar.nearest_key(frame, row.data()) + 0.0f;
          // (The key of one column: a row of copies of it, the same frame.)
          auto key_of_column = [&](std::size_t i) {
            const std::size_t bytes = u16 ? 2 : 4;
            std::vector<std::uint8_t> copies(row.size());
            for (std::size_t j = 0; j < codes.size(); ++j) std::memcpy(copies.data() + j * bytes, row.data() + i * bytes, bytes);
            return scalar.nearest_key(frame, copies.data()) + 0.0f;
          };
          const auto [lo, hi] = std::minmax_element(codes.begin(), codes.end());
          const bool nearer_than_far = whole > frame.key_far;
          low_end += nearer_than_far && key_of_column(static_cast<std::size_t>(lo - codes.begin())) == whole;
          high_end += nearer_than_far && key_of_column(static_cast<std::size_t>(hi - codes.begin())) == whole;
          ++rows;
          for (int a = 0; a < kArchCount; ++a) {
            if (!arch_supported(static_cast<Arch>(a))) continue;
            const float reference = detail::reference_kernels(static_cast<Arch>(a)).nearest_key(frame, row.data()) + 0.0f;
            const float got = detail::compiled_kernels(static_cast<Arch>(a))->nearest_key(frame, row.data()) + 0.0f;
            ASSERT_EQ(std::memcmp(&got, &reference, sizeof got), 0)
                << to_string(static_cast<Arch>(a)) << " format " << static_cast<int>(format) << " width " << width
                << ": " << got << " against the reference's " << reference << " (a " << model.a << ", b " << model.b << ")";
          }
        }
      }
    }
  }
  std::printf("near pass: %ld UNORM rows (%ld by codes), nearest key at the lowest code in %ld, at the highest in %ld\n",
              rows, by_codes, low_end, high_end);
  EXPECT_GT(low_end, rows / 10);  // both ends decide some rows
  EXPECT_GT(high_end, rows / 10);
  EXPECT_GT(by_codes, rows / 2);
}

// b = +-0 (no stereo) is the one model whose mirror is not mirrored in the plan (both eyes get
// s = -1): reproject_pair must still equal two single calls there (fuzz_reproject found the
// shared near key wrong for a = 2^-149, b = 0, scanline, depth 0).
TEST(PairDecode, NoStereoPairEqualsTwoSingleCalls) {
  const int width = 37;
  std::vector<float> depth(width), color(4 * width);
  for (int x = 0; x < width; ++x) depth[x] = x % 5 == 0 ? 0.0f : 0.05f * static_cast<float>(x % 7);
  for (int i = 0; i < 4 * width; ++i) color[i] = static_cast<float>(i % 17) / 16.0f;
  long compared = 0;
  for (const DepthDecoder& decoder : {DepthDecoder::linear(), DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 20.0)}) {
    for (const ParallaxModel model : {ParallaxModel{std::numeric_limits<float>::denorm_min(), 0.0f}, ParallaxModel{5.0f, -0.0f},
                                      ParallaxModel{-3.0f, 0.0f}}) {
      for (int m = 0; m < kMethodCount; ++m) {
        for (bool fixed_near : {false, true}) {
          Options options;
          options.method = static_cast<Method>(m);
          if (fixed_near) options.max_negative_parallax = 2.0f;
          SourceView source;
          source.depth = FloatPlane{depth.data(), width, 1, width};
          source.color = ColorView::rgba(color.data(), width, 1, 4 * width);
          std::vector<float> pair_left(4 * width, -7.0f), pair_right(4 * width, -7.0f), left(4 * width, -7.0f),
              right(4 * width, -7.0f), xs[4];
          for (std::vector<float>& x : xs) x.assign(width, -7.0f);
          auto target = [&](std::vector<float>& c, std::vector<float>& x) {
            TargetView t;
            t.color = MutableColorView::rgba(c.data(), width, 1, 4 * width);
            t.source_x = MutableFloatPlane{x.data(), width, 1, width};
            return t;
          };
          ASSERT_TRUE(reproject_pair(source, decoder, model, options, target(pair_left, xs[0]), target(pair_right, xs[1])).ok());
          ASSERT_TRUE(reproject(source, decoder, ParallaxModel{-model.a, -model.b}, options, target(left, xs[2])).ok());
          ASSERT_TRUE(reproject(source, decoder, model, options, target(right, xs[3])).ok());
          EXPECT_TRUE(same_bits(pair_left, left) && same_bits(xs[0], xs[2])) << "left eye, method " << m << " a " << model.a;
          EXPECT_TRUE(same_bits(pair_right, right) && same_bits(xs[1], xs[3])) << "right eye, method " << m << " a " << model.a;
          ++compared;
        }
      }
    }
  }
  std::printf("no-stereo pairs: %ld compared with two single calls\n", compared);
}

// The log line that says which instruction sets the every-arch tests really executed here (each
// skipped one also says so in its own test). .ci/run prints it.
TEST(EveryArch, WhatRan) {
  const std::string line = arch_report("bit-identity");
  std::printf("%s\n", line.c_str());
  EXPECT_NE(line.find(to_string(selected_arch())), std::string::npos);
  EXPECT_TRUE(arch_supported(Arch::scalar));
}

TEST(Dispatch, SelectedArchIsSupportedAndNamed) {
  const Arch arch = selected_arch();
  EXPECT_TRUE(arch_supported(arch));
  Arch parsed;
  ASSERT_TRUE(parse_arch(to_string(arch), &parsed));
  EXPECT_EQ(parsed, arch);
  EXPECT_FALSE(parse_arch("avx1024", &parsed));
  EXPECT_TRUE(arch_supported(Arch::scalar));
}

TEST(Dispatch, UnsupportedArchIsAnError) {
  for (Arch arch : every_simd_arch()) {
    if (arch_supported(arch)) continue;
    float depth = 1.0f, color = 0.0f, out = 0.0f;
    SourceView source;
    source.depth = FloatPlane{&depth, 1, 1, 1};
    source.color = ColorView::planar({FloatPlane{&color, 1, 1, 1}});
    TargetView target;
    target.color = MutableColorView::planar({MutableFloatPlane{&out, 1, 1, 1}});
    Options options;
    options.arch = arch;
    const Status status = reproject(source, DepthDecoder::linear(), ParallaxModel{1.0f, -1.0f}, options, target);
    EXPECT_EQ(status.code(), StatusCode::invalid_option) << to_string(arch);
  }
}

}  // namespace
}  // namespace reproject
