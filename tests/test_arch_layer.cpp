// Every primitive of the arch layer (kernels/arch_layer.hpp), on every instruction set compiled
// in and supported here, against a scalar statement of its contract with special values in every
// lane position: ArchLayer.<primitive>/<set>, so that a defect (or an xsimd release that changes
// an operation's meaning) names the primitive that broke, not a frame. The checks themselves are
// compiled per set with that set's flags (tests/arch_layer/).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "reproject/reproject.hpp"
#include "support/arch_report.hpp"
#include "tests/arch_layer/sets.hpp"

namespace reproject {
namespace {

class ArchLayer : public ::testing::TestWithParam<Arch> {
 protected:
  void check(test::PrimitiveCheck test::ArchLayerChecks::*primitive, const char* name) {
    const Arch arch = GetParam();
    const test::ArchLayerChecks* checks = test::arch_layer_checks(arch);
    if (!checks) GTEST_SKIP() << to_string(arch) << " is not compiled in for this processor";
    if (!arch_supported(arch)) GTEST_SKIP() << not_run_reason(arch);
    const test::Outcome outcome = (checks->*primitive)();
    if (!outcome.not_applicable.empty()) {
      // Only SSE4.1 lacks a primitive (the permutes): any other set must have them all.
      EXPECT_EQ(arch, Arch::sse) << name << " missing on " << to_string(arch) << ": " << outcome.not_applicable;
      GTEST_SKIP() << name << " on " << to_string(arch) << ": " << outcome.not_applicable;
    }
    EXPECT_GT(outcome.lanes, 0) << name << " checked nothing";
    for (const std::string& message : outcome.messages) ADD_FAILURE() << to_string(arch) << " " << name << ": " << message;
    EXPECT_EQ(outcome.failed, 0) << to_string(arch) << " " << name << ": " << outcome.failed << " of " << outcome.lanes
                                 << " lanes break the contract (the first are listed above)";
    std::printf("%s %s: %ld lanes checked, %ld break the contract\n", to_string(arch), name, outcome.lanes, outcome.failed);
  }
};

#define REPROJECT_ARCH_LAYER_TEST(primitive) \
  TEST_P(ArchLayer, primitive) { check(&test::ArchLayerChecks::primitive, #primitive); }

REPROJECT_ARCH_LAYER_TEST(vmadd)
REPROJECT_ARCH_LAYER_TEST(vdiv)
REPROJECT_ARCH_LAYER_TEST(vfloor)
REPROJECT_ARCH_LAYER_TEST(vmin)
REPROJECT_ARCH_LAYER_TEST(vmax)
REPROJECT_ARCH_LAYER_TEST(round_to_int)
REPROJECT_ARCH_LAYER_TEST(bits_of)
REPROJECT_ARCH_LAYER_TEST(float_bits)
REPROJECT_ARCH_LAYER_TEST(byte_lanes)
REPROJECT_ARCH_LAYER_TEST(gather)
REPROJECT_ARCH_LAYER_TEST(index_for_gather)
REPROJECT_ARCH_LAYER_TEST(lane_extreme)
REPROJECT_ARCH_LAYER_TEST(first_lane)
REPROJECT_ARCH_LAYER_TEST(shift_in_first)
REPROJECT_ARCH_LAYER_TEST(permute)
REPROJECT_ARCH_LAYER_TEST(permute_two_registers)
REPROJECT_ARCH_LAYER_TEST(store_first_lanes)
REPROJECT_ARCH_LAYER_TEST(store_bytes)
REPROJECT_ARCH_LAYER_TEST(load_u16)
REPROJECT_ARCH_LAYER_TEST(store_u16)
REPROJECT_ARCH_LAYER_TEST(pixel4)
REPROJECT_ARCH_LAYER_TEST(lerp4)
REPROJECT_ARCH_LAYER_TEST(blend_rgba8_q15)
REPROJECT_ARCH_LAYER_TEST(srgb_far_pairs)
REPROJECT_ARCH_LAYER_TEST(srgb_decode)
REPROJECT_ARCH_LAYER_TEST(srgb_encode)
REPROJECT_ARCH_LAYER_TEST(srgb_blend)
REPROJECT_ARCH_LAYER_TEST(load_half4)
REPROJECT_ARCH_LAYER_TEST(store_half4)
REPROJECT_ARCH_LAYER_TEST(xsimd_select)
REPROJECT_ARCH_LAYER_TEST(xsimd_compare)
REPROJECT_ARCH_LAYER_TEST(xsimd_masks)
REPROJECT_ARCH_LAYER_TEST(xsimd_convert)
REPROJECT_ARCH_LAYER_TEST(xsimd_integer)
REPROJECT_ARCH_LAYER_TEST(xsimd_arithmetic)

INSTANTIATE_TEST_SUITE_P(EverySet, ArchLayer, ::testing::ValuesIn(every_simd_arch()),
                         [](const ::testing::TestParamInfo<Arch>& info) { return std::string(to_string(info.param)); });

}  // namespace
}  // namespace reproject
