// Bad input. Every invalid call returns its specific StatusCode with a message that
// names the offending thing, and writes nothing (targets pre-filled with sentinels, sources
// compared with a copy). Non-finite and out-of-range depth values are not errors: they have a
// defined result (docs/BEHAVIOUR.md "Non-finite and out-of-range depth"), checked here too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "reproject/reproject.hpp"
#include "support/rows.hpp"

namespace {

using reproject::ColorLayout;
using reproject::DepthDecoder;
using reproject::DepthEncoding;
using reproject::EdgeMode;
using reproject::EyeDirection;
using reproject::HoleFill;
using reproject::Method;
using reproject::Options;
using reproject::ParallaxModel;
using reproject::Status;
using reproject::StatusCode;
using rptest::Encoding;
using rptest::RunResult;
using rptest::SourceFrame;
using rptest::TargetFrame;
using rptest::Tally;

constexpr Method kAllMethods[] = {Method::scanline, Method::march16, Method::single, Method::secant,
                                  Method::exact};
constexpr Method kExactLike[] = {Method::scanline, Method::secant, Method::exact};
constexpr EyeDirection kDirections[] = {EyeDirection::left_to_right, EyeDirection::right_to_left};
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

constexpr int kHit = 0;
constexpr int kHole = 1;
constexpr int kOutside = 2;

// A valid call (named Call, not Setup, which gtest reserves): 24-column source with a guard band of 2 (target 20 columns), 3 rows, 3 colour
// planes (or interleaved RGBA), all strides padded. Each test breaks exactly one thing.
struct Call {
  static constexpr int kSourceWidth = 24;
  static constexpr int kGuard = 2;
  static constexpr int kTargetWidth = kSourceWidth - 2 * kGuard;
  static constexpr int kHeight = 3;

  SourceFrame src;
  TargetFrame dst;
  reproject::SourceView sv;
  reproject::TargetView tv;
  DepthDecoder decoder = DepthDecoder::linear();
  ParallaxModel model;
  Options options;
  std::vector<float> src_copy[5];  // depth, then the colour planes

  explicit Call(ColorLayout layout = ColorLayout::planar)
      : src(rptest::make_source(kSourceWidth, kHeight, 3, layout, 2)),
        dst(rptest::make_target(kTargetWidth, kHeight, 3, layout, 3)) {
    src.set_depth([](int, int) { return 3.0; });
    sv = src.view();
    tv = dst.view();
    model = ParallaxModel::from_stereo(0.05, 2.0, kTargetWidth, EyeDirection::left_to_right);
    options.guard = kGuard;
    src_copy[0] = src.depth;
    for (int c = 0; c < 4; ++c) src_copy[1 + c] = src.color[c];
  }
  Call(const Call&) = delete;
  Call& operator=(const Call&) = delete;

  Status call() const { return reproject::reproject(sv, decoder, model, options, tv); }
  bool nothing_written() const {
    if (!dst.all_untouched()) return false;
    if (!(src.depth == src_copy[0])) return false;
    for (int c = 0; c < 4; ++c)
      if (!(src.color[c] == src_copy[1 + c])) return false;
    return true;
  }
  // Every plane of the target view (colour and the optional ones): for changes that apply to all.
  template <class F>
  void for_each_target_plane(F f) {
    for (int c = 0; c < tv.color.channels && c < 4; ++c) f(tv.color.plane[c]);
    f(tv.depth);
    f(tv.source_x);
    f(tv.status);
  }
  template <class F>
  void for_each_source_plane(F f) {
    for (int c = 0; c < sv.color.channels && c < 4; ++c) f(sv.color.plane[c]);
    f(sv.depth);
  }
};

std::string lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

using Words = std::vector<const char*>;

bool mentions(const char* message, const Words& words) {
  const std::string m = lower(message);
  for (const char* w : words)
    if (m.find(lower(w)) != std::string::npos) return true;
  return false;
}

std::string join(const Words& words) {
  std::string s;
  for (const char* w : words) s += std::string(s.empty() ? "" : "|") + w;
  return s;
}

// The call is rejected with `code`, a message naming one of `words`, and no write anywhere.
void expect_rejected(const Call& setup, StatusCode code, const Words& words,
                     const std::string& what) {
  const Status st = setup.call();
  EXPECT_EQ(st.code(), code) << what << ": got " << reproject::to_string(st.code()) << " \"" << st.message()
                             << "\", expected " << reproject::to_string(code);
  EXPECT_GT(std::strlen(st.message()), 0u) << what;
  if (!st.ok()) {
    EXPECT_TRUE(mentions(st.message(), words)) << what << ": message \"" << st.message()
                                               << "\" names none of " << join(words);
  }
  EXPECT_TRUE(setup.nothing_written()) << what << ": an invalid call wrote output";
}

TEST(BadInputBaseline, TheUnbrokenSetupsAreValid) {
  // Guards the other tests: each breaks one thing of a call that is otherwise accepted.
  for (ColorLayout layout : {ColorLayout::planar, ColorLayout::interleaved_rgba}) {
    Call s(layout);
    const Status st = s.call();
    EXPECT_TRUE(st.ok()) << st.message();
    EXPECT_TRUE(s.dst.padding_untouched());
  }
}

TEST(BadInputPointers, NullColorOrDepth) {
  {
    Call s;
    s.sv.color.plane[0].data = nullptr;
    expect_rejected(s, StatusCode::null_pointer, {"colo"}, "source colour plane 0 null");
  }
  {
    Call s;
    s.sv.color.plane[2].data = nullptr;
    expect_rejected(s, StatusCode::null_pointer, {"colo"}, "source colour plane 2 null");
  }
  {
    Call s(ColorLayout::interleaved_rgba);
    s.sv.color.plane[0].data = nullptr;
    expect_rejected(s, StatusCode::null_pointer, {"colo"}, "source interleaved colour null");
  }
  {
    Call s;
    s.sv.depth.data = nullptr;
    expect_rejected(s, StatusCode::null_pointer, {"depth"}, "source depth null");
  }
  {
    Call s;
    s.tv.color.plane[0].data = nullptr;
    expect_rejected(s, StatusCode::null_pointer, {"colo"}, "target colour plane 0 null");
  }
  {
    Call s;
    s.tv.color.plane[1].data = nullptr;
    expect_rejected(s, StatusCode::null_pointer, {"colo"}, "target colour plane 1 null");
  }
}

TEST(BadInputPointers, OptionalOutputsMayBeNull) {
  Call s;
  s.tv.depth.data = nullptr;
  s.tv.status.data = nullptr;
  s.tv.source_x.data = nullptr;
  const Status st = s.call();
  EXPECT_TRUE(st.ok()) << st.message();
}

TEST(BadInputSizes, NegativeWidthOrHeight) {
  {
    Call s;  // consistent: source -1, target -1 - 2 guard
    s.for_each_source_plane([](auto& p) { p.width = -1; });
    s.for_each_target_plane([](auto& p) { p.width = -1 - 2 * Call::kGuard; });
    expect_rejected(s, StatusCode::invalid_size, {"width", "size"}, "negative widths");
  }
  {
    Call s;
    s.options.guard = 0;
    s.for_each_source_plane([](auto& p) { p.width = -3; });
    s.for_each_target_plane([](auto& p) { p.width = -3; });
    expect_rejected(s, StatusCode::invalid_size, {"width", "size"}, "negative widths, no guard");
  }
  {
    Call s;
    s.for_each_source_plane([](auto& p) { p.height = -2; });
    s.for_each_target_plane([](auto& p) { p.height = -2; });
    expect_rejected(s, StatusCode::invalid_size, {"height", "size"}, "negative heights");
  }
}

TEST(BadInputSizes, GuardBandLeavingNoTargetColumns) {
  {
    Call s;  // 24 - 2 * 13 < 0
    s.options.guard = 13;
    expect_rejected(s, StatusCode::invalid_size, {"guard"}, "guard 13 on a 24-column source");
  }
  {
    Call s;  // 24 - 2 * 12 == 0 target columns: status.hpp calls this invalid_size
    s.options.guard = 12;
    s.for_each_target_plane([](auto& p) { p.width = 0; });
    expect_rejected(s, StatusCode::invalid_size, {"guard"}, "guard 12 on a 24-column source");
  }
}

TEST(BadInputStrides, StrideSmallerThanTheRow) {
  const int ws = Call::kSourceWidth;
  const int wt = Call::kTargetWidth;
  {
    Call s;
    s.sv.depth.stride = ws - 1;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "source depth stride < width");
  }
  {
    Call s;
    s.sv.color.plane[1].stride = ws - 1;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "source colour plane 1 stride < width");
  }
  {
    Call s;
    s.sv.depth.stride = -ws;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "negative source depth stride");
  }
  {
    Call s;
    s.tv.color.plane[0].stride = wt - 1;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "target colour stride < width");
  }
  {
    Call s;
    s.tv.depth.stride = wt - 1;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "target depth stride < width");
  }
  {
    Call s;
    s.tv.status.stride = wt - 1;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "target status stride < width");
  }
  {
    Call s;
    s.tv.source_x.stride = wt - 1;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "target source_x stride < width");
  }
  {
    Call s(ColorLayout::interleaved_rgba);
    s.sv.color.plane[0].stride = 4 * ws - 1;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "interleaved source stride 4w - 1");
  }
  {
    Call s(ColorLayout::interleaved_rgba);
    s.sv.color.plane[0].stride = ws + 2;  // enough for a planar row, not for RGBA
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "interleaved source stride w + 2");
  }
  {
    Call s(ColorLayout::interleaved_rgba);
    s.tv.color.plane[0].stride = 4 * wt - 1;
    expect_rejected(s, StatusCode::invalid_stride, {"stride"}, "interleaved target stride 4w - 1");
  }
}

TEST(BadInputMismatch, SizesBetweenBuffers) {
  const int ws = Call::kSourceWidth;
  const int wt = Call::kTargetWidth;
  const int h = Call::kHeight;
  const Words size_words = {"width", "height", "size"};
  {
    Call s;  // target one column wider than source - 2 guard
    s.for_each_target_plane([](auto& p) { p.width += 1; });
    expect_rejected(s, StatusCode::size_mismatch, size_words, "target width != source width - 2 guard");
  }
  {
    Call s;
    s.options.guard = 1;  // the same buffers now disagree by two columns
    expect_rejected(s, StatusCode::size_mismatch, size_words, "guard 1 with a 2-guard target");
  }
  {
    Call s;
    s.for_each_target_plane([](auto& p) { p.height -= 1; });
    expect_rejected(s, StatusCode::size_mismatch, size_words, "target height != source height");
  }
  {
    Call s;
    s.sv.depth.width = ws - 1;
    expect_rejected(s, StatusCode::size_mismatch, size_words, "depth width != colour width");
  }
  {
    Call s;
    s.sv.depth.height = h - 1;
    expect_rejected(s, StatusCode::size_mismatch, size_words, "depth height != colour height");
  }
  {
    Call s;
    s.sv.color.plane[1].width = ws - 1;
    expect_rejected(s, StatusCode::size_mismatch, size_words, "source colour plane 1 narrower");
  }
  {
    Call s;
    s.sv.color.plane[2].height = h - 1;
    expect_rejected(s, StatusCode::size_mismatch, size_words, "source colour plane 2 shorter");
  }
  {
    Call s;
    s.tv.color.plane[1].width = wt - 1;
    expect_rejected(s, StatusCode::size_mismatch, size_words, "target colour plane 1 narrower");
  }
  {
    Call s;
    s.tv.depth.width = wt - 1;
    expect_rejected(s, StatusCode::size_mismatch, size_words, "target depth narrower");
  }
  {
    Call s;
    s.tv.status.height = h - 1;
    expect_rejected(s, StatusCode::size_mismatch, size_words, "target status shorter");
  }
  {
    Call s;
    s.tv.source_x.width = wt - 1;
    expect_rejected(s, StatusCode::size_mismatch, size_words, "target source_x narrower");
  }
}

TEST(BadInputMismatch, ChannelCountsAndLayouts) {
  const Words words = {"channel", "layout", "interleav", "planar"};
  {
    Call s;  // source 3 planes, target 2
    s.tv.color.channels = 2;
    expect_rejected(s, StatusCode::size_mismatch, words, "3 source channels, 2 target channels");
  }
  {
    Call s;  // source 2 planes, target 3
    s.sv.color.channels = 2;
    expect_rejected(s, StatusCode::size_mismatch, words, "2 source channels, 3 target channels");
  }
  {
    // Interleaved RGBA source, 4 planar target planes.
    Call s(ColorLayout::interleaved_rgba);
    TargetFrame planar = rptest::make_target(Call::kTargetWidth, Call::kHeight, 4, ColorLayout::planar, 3);
    s.tv.color = planar.view().color;
    expect_rejected(s, StatusCode::size_mismatch, words, "interleaved source, planar target");
    EXPECT_TRUE(planar.all_untouched());
  }
  {
    // 4 planar source planes, interleaved target.
    SourceFrame planar = rptest::make_source(Call::kSourceWidth, Call::kHeight, 4, ColorLayout::planar, 2);
    Call s(ColorLayout::interleaved_rgba);
    s.sv.color = planar.view().color;
    expect_rejected(s, StatusCode::size_mismatch, words, "planar source, interleaved target");
  }
}

TEST(BadInputAliasing, OutputsOverlappingInputsOrEachOther) {
  const int wt = Call::kTargetWidth;
  const int h = Call::kHeight;
  const Words words = {"overlap", "alias"};
  {
    Call s;  // target colour plane 0 is the source depth plane
    s.tv.color.plane[0] = reproject::MutableFloatPlane{s.src.depth.data(), wt, h, s.src.stride};
    expect_rejected(s, StatusCode::aliasing, words, "target colour = source depth");
  }
  {
    Call s;  // target depth starts 3 floats into source colour plane 1: overlapping ranges
    s.tv.depth = reproject::MutableFloatPlane{s.src.color[1].data() + 3, wt, h, s.src.stride};
    expect_rejected(s, StatusCode::aliasing, words, "target depth inside source colour plane 1");
  }
  {
    // The last row of the source depth overlaps the first of the target source_x. Both live in one
    // buffer big enough for either view, so even a wrong write stays in our memory.
    Call s;
    const std::ptrdiff_t stride = s.src.stride;
    std::vector<float> big(static_cast<std::size_t>(2 * h * stride), 3.0f);
    s.sv.depth = reproject::FloatPlane{big.data(), Call::kSourceWidth, h, stride};
    s.tv.source_x = reproject::MutableFloatPlane{big.data() + (h - 1) * stride + 3, wt, h, stride};
    const std::vector<float> before = big;
    expect_rejected(s, StatusCode::aliasing, words, "target source_x overlapping the end of source depth");
    EXPECT_EQ(big, before);
  }
  {
    Call s;  // two outputs on the same memory
    s.tv.source_x = s.tv.depth;
    expect_rejected(s, StatusCode::aliasing, words, "target source_x = target depth");
  }
  {
    Call s;
    s.tv.color.plane[1] = s.tv.color.plane[0];
    expect_rejected(s, StatusCode::aliasing, words, "target colour planes 0 and 1 the same");
  }
  {
    Call s;  // the byte status plane inside the float depth plane
    s.tv.status.data = reinterpret_cast<std::uint8_t*>(s.dst.depth.data()) + 5;
    expect_rejected(s, StatusCode::aliasing, words, "target status inside target depth");
  }
  {
    // An interleaved target over the source depth, in one buffer that holds either view.
    Call s(ColorLayout::interleaved_rgba);
    std::vector<float> big(static_cast<std::size_t>(h * s.dst.color_stride), 3.0f);
    s.sv.depth = reproject::FloatPlane{big.data(), Call::kSourceWidth, h, s.src.stride};
    s.tv.color.plane[0] = reproject::MutableFloatPlane{big.data(), wt, h, s.dst.color_stride};
    const std::vector<float> before = big;
    expect_rejected(s, StatusCode::aliasing, words, "interleaved target colour over source depth");
    EXPECT_EQ(big, before);
  }
}

TEST(BadInputAliasing, DisjointPlanesOfOneBufferAreFine) {
  // Source depth rows followed immediately by the target depth rows in one allocation (stride ==
  // width, so the ranges touch but do not overlap); and an input read twice (inputs may share).
  Call s;
  const int ws = Call::kSourceWidth;
  const int wt = Call::kTargetWidth;
  const int h = Call::kHeight;
  std::vector<float> one(static_cast<std::size_t>(ws * h + wt * h), rptest::kUntouched);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < ws; ++x) one[static_cast<std::size_t>(y * ws + x)] = s.src.depth_at(x, y);
  s.sv.depth = reproject::FloatPlane{one.data(), ws, h, ws};
  s.tv.depth = reproject::MutableFloatPlane{one.data() + ws * h, wt, h, wt};
  s.sv.color.plane[2] = s.sv.color.plane[0];
  const Status st = s.call();
  EXPECT_TRUE(st.ok()) << st.message();
  for (int i = 0; i < ws * h; ++i) EXPECT_EQ(one[static_cast<std::size_t>(i)], 3.0f);
  for (int i = ws * h; i < ws * h + wt * h; ++i) EXPECT_NEAR(one[static_cast<std::size_t>(i)], 3.0f, 1e-5f);
}

TEST(BadInputModel, NonFiniteOrDegenerateParameters) {
  const Words words = {"model", "parallax", "convergence", "nan", "inf"};
  const int wt = Call::kTargetWidth;
  struct Case {
    ParallaxModel model;
    const char* what;
  };
  const Case cases[] = {
      {ParallaxModel::from_stereo(0.05, 0.0, wt, EyeDirection::left_to_right), "from_stereo convergence 0"},
      {ParallaxModel::from_stereo(0.05, -2.0, wt, EyeDirection::right_to_left), "from_stereo convergence -2"},
      {ParallaxModel{kNaN, -1.0f}, "a = NaN"},
      {ParallaxModel{1.0f, kInf}, "b = +inf"},
      {ParallaxModel{1.0f, -kInf}, "b = -inf"},
      {ParallaxModel{kInf, -1.0f}, "a = +inf"},
  };
  for (const Case& c : cases) {
    for (Method method : kAllMethods) {
      Call s;
      s.model = c.model;
      s.options.method = method;
      expect_rejected(s, StatusCode::invalid_model, words, std::string(c.what) + " / " + reproject::to_string(method));
    }
  }
}

TEST(BadInputDecoder, InvalidNearFar) {
  const Words words = {"near", "far", "decoder"};
  struct Case {
    DepthDecoder decoder;
    const char* what;
  };
  const Case cases[] = {
      {DepthDecoder::from_near_far(DepthEncoding::standard, 0.0, 10.0), "standard near 0"},
      {DepthDecoder::from_near_far(DepthEncoding::standard, -1.0, 10.0), "standard near -1"},
      {DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 1.0), "standard far == near"},
      {DepthDecoder::from_near_far(DepthEncoding::standard, 2.0, 1.0), "standard far < near"},
      {DepthDecoder::from_near_far(DepthEncoding::gl_ndc, 1.0, 0.5), "gl_ndc far < near"},
      {DepthDecoder::from_near_far(DepthEncoding::reversed, 0.0, 10.0), "reversed near 0"},
      {DepthDecoder::from_near_far(DepthEncoding::reversed_infinite, -0.1, 0.0), "reversed_infinite near < 0"},
      {DepthDecoder::from_near_far(DepthEncoding::standard, std::nan(""), 10.0), "standard near NaN"},
  };
  for (const Case& c : cases) {
    Call s;
    s.decoder = c.decoder;
    expect_rejected(s, StatusCode::invalid_decoder, words, c.what);
  }
}

TEST(BadInputOptions, OutOfRangeFields) {
  struct Case {
    void (*apply)(Options&);
    Words words;
    const char* what;
  };
  const Case cases[] = {
      {[](Options& o) { o.hole_threshold = -0.5f; }, {"hole_threshold", "threshold", "tau"}, "hole_threshold -0.5"},
      {[](Options& o) { o.hole_threshold = kNaN; }, {"hole_threshold", "threshold", "tau"}, "hole_threshold NaN"},
      {[](Options& o) { o.march_steps = 0; }, {"march"}, "march_steps 0"},
      {[](Options& o) { o.march_steps = -4; }, {"march"}, "march_steps -4"},
      {[](Options& o) { o.march_steps = 1025; }, {"march"}, "march_steps 1025"},
      {[](Options& o) { o.secant_max_steps = 0; }, {"secant"}, "secant_max_steps 0"},
      {[](Options& o) { o.secant_max_steps = 4097; }, {"secant"}, "secant_max_steps 4097"},
      {[](Options& o) { o.guard = -1; }, {"guard"}, "guard -1"},
      {[](Options& o) { o.max_negative_parallax = -1.0f; }, {"max_negative_parallax", "negative"}, "max_negative_parallax -1"},
      {[](Options& o) { o.max_negative_parallax = kNaN; }, {"max_negative_parallax", "negative"}, "max_negative_parallax NaN"},
      {[](Options& o) { o.probe_parallax = kNaN; }, {"probe"}, "probe_parallax NaN"},
  };
  // "Validates everything once" (reproject.hpp): a bad field is rejected whichever method runs.
  for (const Case& c : cases) {
    for (Method method : kAllMethods) {
      Call s;
      s.options.method = method;
      c.apply(s.options);
      expect_rejected(s, StatusCode::invalid_option, c.words, std::string(c.what) + " / " + reproject::to_string(method));
    }
  }
}

TEST(BadInputEmpty, ZeroWidthOrHeightIsOkAndWritesNothing) {
  for (Method method : kAllMethods) {
    {
      Call s;
      s.options.method = method;
      s.options.guard = 0;
      s.for_each_source_plane([](auto& p) { p.width = 0; });
      s.for_each_target_plane([](auto& p) { p.width = 0; });
      const Status st = s.call();
      EXPECT_TRUE(st.ok()) << "width 0 / " << reproject::to_string(method) << ": " << st.message();
      EXPECT_TRUE(s.nothing_written()) << "width 0 / " << reproject::to_string(method);
    }
    {
      Call s;
      s.options.method = method;
      s.for_each_source_plane([](auto& p) { p.height = 0; });
      s.for_each_target_plane([](auto& p) { p.height = 0; });
      const Status st = s.call();
      EXPECT_TRUE(st.ok()) << "height 0 / " << reproject::to_string(method) << ": " << st.message();
      EXPECT_TRUE(s.nothing_written()) << "height 0 / " << reproject::to_string(method);
    }
  }
}

// --------------------------------------------------------------------------------------------
// Non-finite and out-of-range depth (docs/BEHAVIOUR.md): NaN, and anything that decodes to w < 0, is
// infinitely far (p = p_far = a); w = +inf (linear depth 0, standard -inf) and anything nearer
// than L = Ws + 2 pixels is clamped to s L, "the nearest possible".
// --------------------------------------------------------------------------------------------

Encoding linear_encoding() { return {DepthEncoding::linear, 0.0, 0.0}; }
Encoding standard_encoding() { return {DepthEncoding::standard, 0.2, 100.0}; }

bool same_color_status_x(const RunResult& a, const RunResult& b, std::string* why) {
  for (int y = 0; y < a.out.height; ++y)
    for (int t = 0; t < a.out.width; ++t) {
      if (!(a.out.x_at(t, y) == b.out.x_at(t, y))) {
        *why = "source_x differs at t=" + std::to_string(t) + ": " + std::to_string(a.out.x_at(t, y)) + " vs " +
               std::to_string(b.out.x_at(t, y));
        return false;
      }
      if (a.out.status_at(t, y) != b.out.status_at(t, y)) {
        *why = "status differs at t=" + std::to_string(t) + ": " + std::to_string(a.out.status_at(t, y)) + " vs " +
               std::to_string(b.out.status_at(t, y));
        return false;
      }
      for (int c = 0; c < a.out.channels; ++c)
        if (!(a.out.color_at(c, t, y) == b.out.color_at(c, t, y))) {
          *why = "colour" + std::to_string(c) + " differs at t=" + std::to_string(t) + ": " +
                 std::to_string(a.out.color_at(c, t, y)) + " vs " + std::to_string(b.out.color_at(c, t, y));
          return false;
        }
    }
  return true;
}

// A far wall (z = 6, p_f) with one special pixel at column k. When the pixel acts as infinitely
// far (p = a, a tear of D = |a - p_f| > 1 on one side, a fold on the other), the exact answer has a
// 2-px hole filled from column k itself (the wall's farther endpoint):
//   s < 0: t' in [k - 1 + p_f, k + 1 + p_f)     s > 0: t' in (k - 1 + p_f, k + 1 + p_f]
// and every other target sees the wall at x = t' - p_f.
TEST(BadInputDepth, NaNAndFartherThanInfinityActAsInfinitelyFar) {
  const int width = 64;
  const int k = 30;
  struct Value {
    float v;
    const char* what;
  };
  for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
    const bool linear = enc.encoding == DepthEncoding::linear;
    // The reference: exactly at infinity for linear (w = 1/inf = 0, p = a exactly); for standard
    // +inf stored decodes to w = -inf, farther than infinity.
    const std::vector<Value> values =
        linear ? std::vector<Value>{{kInf, "+inf"}, {kNaN, "NaN"}, {-kInf, "-inf"}, {-5.0f, "-5"}}
               : std::vector<Value>{{kInf, "+inf"}, {kNaN, "NaN"}, {5.0f, "5 (beyond far)"}, {1.5f, "1.5 (beyond far)"}};
    for (EyeDirection dir : kDirections) {
      const ParallaxModel model = ParallaxModel::from_stereo(0.12, 2.0, width, dir);  // a = ±7.68
      const int s = model.b > 0.0f ? 1 : -1;
      const float wall = enc.stored(1.0 / 6.0);
      const double p_f = static_cast<double>(model.a) + static_cast<double>(model.b) * enc.w(wall);
      ASSERT_GT(std::fabs(model.a - p_f), 1.0);
      for (Method method : kAllMethods) {
        Options options;
        options.method = method;
        std::vector<RunResult> runs;
        for (const Value& value : values) {
          SourceFrame src = rptest::make_source(width, 1, 2);
          src.set_depth([&](int x, int) { return x == k ? value.v : wall; });
          runs.push_back(rptest::run(src, enc.decoder(), model, options));
          const RunResult& r = runs.back();
          const std::string ctx = std::string(reproject::to_string(method)) + "/" + reproject::to_string(dir) + "/" +
                                  enc.name() + "/" + value.what;
          ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
          std::string why;
          EXPECT_TRUE(same_color_status_x(runs.front(), r, &why)) << ctx << " differs from +inf: " << why;

          bool exact_like = false;
          for (Method m : kExactLike) exact_like |= m == method;
          if (!exact_like) continue;
          Tally tally;
          int holes = 0;
          for (int t = 0; t < width; ++t) {
            const double lo = k - 1 + p_f, hi = k + 1 + p_f;
            const bool hole = s < 0 ? (t >= lo && t < hi) : (t > lo && t <= hi);
            const double x = t - p_f;
            const int want = hole ? kHole : (x < 0.0 || x > width - 1 ? kOutside : kHit);
            const int got = r.out.status_at(t, 0);
            holes += got == kHole;
            if (got != want) tally.fail("%s t=%d: status %d, expected %d", ctx.c_str(), t, got, want);
            const double c0 = r.out.color_at(0, t, 0);
            const double want_c0 = hole ? k : std::min(std::max(x, 0.0), width - 1.0);
            if (!(std::fabs(c0 - want_c0) <= 1e-3)) tally.fail("%s t=%d: colour %.5f, expected %.5f", ctx.c_str(), t, c0, want_c0);
            const float d = r.out.depth_at(t, 0);
            if (hole && std::isnan(value.v) && !std::isnan(d))
              tally.fail("%s t=%d: hole filled from the NaN pixel has depth %g, expected NaN", ctx.c_str(), t, d);
            if (!hole && !(std::fabs(d - wall) <= 1e-5f * std::max(1.0f, std::fabs(wall))))
              tally.fail("%s t=%d: wall depth %g, expected %g", ctx.c_str(), t, d, wall);
          }
          EXPECT_EQ(holes, 2) << ctx;
          EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
        }
      }
    }
  }
}

// A pixel with linear depth 0 (w = +inf) is clamped to the nearest possible parallax s L: its tear
// reaches past the whole row, so every target on that side is a hole filled with the wall's
// farther endpoint next to it:
//   s < 0: t' < k + 1 + p_f holes (fill column k + 1), the rest wall or outside (t' > W - 1 + p_f)
//   s > 0: t' > k - 1 + p_f holes (fill column k - 1), the rest wall or outside (t' < p_f)
// Any other value as near or nearer (1e-30, standard -inf or -1e30) gives the same picture.
// The decode is shared, so that equivalence holds for every method with default options. The
// exact picture is asserted for exact and scanline, and for secant with a step cap that allows
// one-pixel steps over the whole ray (|s L - a| ~ 74 px here): docs/BEHAVIOUR.md "Methods" bounds secant's steps to a
// pixel only "where possible", and with the default cap of 64 a 1-px spike can be stepped over.
TEST(BadInputDepth, ZeroLinearDepthIsTheNearestPossible) {
  const int width = 64;
  const int k = 30;
  struct Value {
    Encoding enc;
    float v;
    const char* what;
  };
  const Value values[] = {{linear_encoding(), 0.0f, "linear 0"},
                          {linear_encoding(), 1e-30f, "linear 1e-30"},
                          {standard_encoding(), -kInf, "standard -inf"},
                          {standard_encoding(), -1e30f, "standard -1e30"}};
  for (EyeDirection dir : kDirections) {
    const ParallaxModel model = ParallaxModel::from_stereo(0.12, 2.0, width, dir);
    const int s = model.b > 0.0f ? 1 : -1;
    for (Method method : kAllMethods) {
      Options options;
      options.method = method;
      // values come in pairs of one encoding; the first of each pair is the second's reference.
      std::vector<RunResult> runs;
      for (std::size_t i = 0; i < sizeof values / sizeof values[0]; ++i) {
        const Value& value = values[i];
        const Encoding& enc = value.enc;
        const float wall = enc.stored(1.0 / 6.0);
        const double p_f = static_cast<double>(model.a) + static_cast<double>(model.b) * enc.w(wall);
        SourceFrame src = rptest::make_source(width, 1, 2);
        src.set_depth([&](int x, int) { return x == k ? value.v : wall; });
        runs.push_back(rptest::run(src, enc.decoder(), model, options));
        const RunResult& r = runs.back();
        const std::string ctx = std::string(reproject::to_string(method)) + "/" + reproject::to_string(dir) + "/" + value.what;
        ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
        std::string why;
        const std::size_t reference = i - i % 2;
        EXPECT_TRUE(same_color_status_x(runs[reference], r, &why))
            << ctx << " differs from " << values[reference].what << ": " << why;
        for (int t = 0; t < width; ++t)
          EXPECT_LE(r.out.status_at(t, 0), 3) << ctx;

        bool exact_like = false;
        for (Method m : kExactLike) exact_like |= m == method;
        if (!exact_like) continue;
        RunResult uncapped;
        if (method == Method::secant) {
          Options fine = options;
          fine.secant_max_steps = 4096;
          uncapped = rptest::run(src, enc.decoder(), model, fine);
          ASSERT_TRUE(uncapped.status.ok()) << ctx << ": " << uncapped.status.message();
        }
        const RunResult& checked = method == Method::secant ? uncapped : r;
        Tally tally;
        for (int t = 0; t < width; ++t) {
          const bool hole = s < 0 ? t < k + 1 + p_f : t > k - 1 + p_f;
          const double x = t - p_f;
          const int want = hole ? kHole : (x < 0.0 || x > width - 1 ? kOutside : kHit);
          const int got = checked.out.status_at(t, 0);
          if (got != want) tally.fail("%s t=%d: status %d, expected %d", ctx.c_str(), t, got, want);
          const double c0 = checked.out.color_at(0, t, 0);
          const double want_c0 = hole ? (s < 0 ? k + 1 : k - 1) : std::min(std::max(x, 0.0), width - 1.0);
          if (!(std::fabs(c0 - want_c0) <= 1e-3)) tally.fail("%s t=%d: colour %.5f, expected %.5f", ctx.c_str(), t, c0, want_c0);
          const float d = checked.out.depth_at(t, 0);
          if (!(std::fabs(d - wall) <= 1e-5f * std::max(1.0f, std::fabs(wall))))
            tally.fail("%s t=%d: depth %g, expected the wall's %g", ctx.c_str(), t, d, wall);
        }
        EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
      }
    }
  }
}

// Random rows sprinkled with NaN, +-inf, 0, negative, tiny and huge values: never a crash or an
// error, every status one of the four, source_x finite (parallax is clamped to [-L, L] or set to
// p_far, so x = t' - P always is), colour finite where written, nothing beyond the width written.
TEST(BadInputDepth, GarbageDepthNeverBreaksTheOutput) {
  const int target_width = 53;
  const int height = 6;
  std::mt19937 rng(77u);
  const float specials[] = {kNaN, kInf, -kInf, 0.0f, -0.0f, -3.0f, 1e-30f, 1e30f, -1e30f, 0.5f, 1.0f, 2.0f};
  for (const Encoding& enc : {linear_encoding(), standard_encoding()}) {
    for (int guard : {0, 3}) {
      SourceFrame src = rptest::make_source(target_width + 2 * guard, height, 2, ColorLayout::planar, 2);
      src.set_depth([&](int, int) {
        const unsigned r = rng() % 100u;
        if (r < 30u) return static_cast<double>(specials[rng() % (sizeof specials / sizeof specials[0])]);
        // An ordinary depth in range for either encoding.
        const double z = 0.5 + 20.0 * (rng() % 1000u) / 1000.0;
        return static_cast<double>(enc.stored(1.0 / z));
      });
      for (EyeDirection dir : kDirections) {
        const ParallaxModel model = ParallaxModel::from_stereo(0.08, 2.0, target_width, dir);
        for (Method method : kAllMethods) {
          for (int variant = 0; variant < 4; ++variant) {
            Options options;
            options.method = method;
            options.guard = guard;
            options.hole_fill = variant == 1 ? HoleFill::none : variant == 2 ? HoleFill::foreground : HoleFill::background;
            options.edge = variant == 1 ? EdgeMode::none : EdgeMode::clamp;
            if (variant == 3) options.max_negative_parallax = 2.5f;
            const RunResult r = rptest::run(src, enc.decoder(), model, options);
            const std::string ctx = std::string(reproject::to_string(method)) + "/" + reproject::to_string(dir) + "/" +
                                    enc.name() + "/guard" + std::to_string(guard) + "/variant" + std::to_string(variant);
            ASSERT_TRUE(r.status.ok()) << ctx << ": " << r.status.message();
            EXPECT_TRUE(r.out.padding_untouched()) << ctx;
            Tally tally;
            for (int y = 0; y < height; ++y)
              for (int t = 0; t < target_width; ++t) {
                const int st = r.out.status_at(t, y);
                if (st > 3) tally.fail("%s t=%d y=%d: status %d", ctx.c_str(), t, y, st);
                if (!std::isfinite(r.out.x_at(t, y))) tally.fail("%s t=%d y=%d: source_x %g", ctx.c_str(), t, y, r.out.x_at(t, y));
                for (int c = 0; c < 2; ++c) {
                  const float v = r.out.color_at(c, t, y);
                  const bool may_skip = (st == kHole && options.hole_fill == HoleFill::none) ||
                                        (st == kOutside && options.edge == EdgeMode::none);
                  if (!std::isfinite(v) || (v == rptest::kUntouched && !may_skip))
                    tally.fail("%s t=%d y=%d: colour%d %g (status %d)", ctx.c_str(), t, y, c, v, st);
                }
              }
            EXPECT_EQ(tally.count(), 0) << ctx << tally.report();
          }
        }
      }
    }
  }
}

}  // namespace
