// Every public enum's names (reproject.hpp, before to_string(Method)): each value prints a name
// its parser reads back, an unknown value prints "unknown", and every parser treats a null name,
// an unknown name and a null `out` the same way.
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>

#include "reproject/formats.hpp"
#include "reproject/reproject.hpp"

namespace reproject {
namespace {

template <class E>
void expect_names(int count, bool (*parse)(const char*, E*), const std::set<std::string>& expected) {
  std::set<std::string> seen;
  for (int i = 0; i < count; ++i) {
    const E value = static_cast<E>(i);
    const char* name = to_string(value);
    ASSERT_NE(name, nullptr);
    EXPECT_STRNE(name, "unknown") << i;
    seen.insert(name);
    E parsed = static_cast<E>(count == 1 ? 0 : (i + 1) % count);
    EXPECT_TRUE(parse(name, &parsed)) << name;
    EXPECT_EQ(parsed, value) << name;
    EXPECT_TRUE(parse(name, nullptr)) << name;  // a null out only checks the name
  }
  EXPECT_EQ(seen, expected);
  EXPECT_STREQ(to_string(static_cast<E>(count)), "unknown");
  EXPECT_STREQ(to_string(static_cast<E>(255)), "unknown");
  E untouched = static_cast<E>(count - 1);
  for (const char* bad : {"", "unknown", "EXACT", " exact", "avx-512", "none "}) {
    if (expected.count(bad)) continue;
    EXPECT_FALSE(parse(bad, &untouched)) << bad;
    EXPECT_FALSE(parse(bad, nullptr)) << bad;
  }
  EXPECT_FALSE(parse(nullptr, &untouched));
  EXPECT_FALSE(parse(nullptr, nullptr));
  EXPECT_EQ(untouched, static_cast<E>(count - 1));
}

TEST(Names, EveryEnumRoundTripsAndParsesAlike) {
  expect_names<Method>(kMethodCount, parse_method, {"scanline", "march16", "single", "secant", "exact"});
  expect_names<Arch>(kArchCount, parse_arch, {"scalar", "sse", "avx2", "avx512", "neon"});
  expect_names<HoleFill>(kHoleFillCount, parse_hole_fill, {"background", "foreground", "none"});
  expect_names<EdgeMode>(kEdgeModeCount, parse_edge_mode, {"clamp", "none", "black", "mirror"});
  expect_names<DepthEncoding>(kDepthEncodingCount, parse_encoding,
                              {"linear", "standard", "gl_ndc", "reversed", "reversed_infinite", "infinite", "disparity"});
  expect_names<EyeDirection>(kEyeDirectionCount, parse_direction,
                             {"left-to-right", "right-to-left", "centre-to-left", "centre-to-right"});
  expect_names<ColorFormat>(kColorFormatCount, parse_color_format, {"float32", "rgba8", "rgba8_srgb", "rgba16f"});
  expect_names<DepthFormat>(kDepthFormatCount, parse_depth_format,
                            {"float32", "unorm16", "unorm24_s8", "s8_unorm24", "rgba8_packed_linear"});
}

TEST(Names, DirectionsAcceptTheUnderscoreSpelling) {
  EyeDirection d = EyeDirection::left_to_right;
  EXPECT_TRUE(parse_direction("centre_to_right", &d));
  EXPECT_EQ(d, EyeDirection::centre_to_right);
  EXPECT_STREQ(to_string(d), "centre-to-right");  // printed with hyphens
}

}  // namespace
}  // namespace reproject
