// The arch layer's contracts (kernels/arch_layer.hpp) stated as scalar code, and one check per
// primitive that holds a set's vectors to it lane by lane, with special values in every lane
// position (tests/arch_layer/values.hpp). Instantiated per set by tests/arch_layer/set.cpp, with
// that set's flags; tests/test_arch_layer.cpp runs every check on every set the CPU has.
#pragma once

#include "tests/arch_layer/checks_arithmetic.hpp"
#include "tests/arch_layer/checks_memory.hpp"
#include "tests/arch_layer/checks_pixels.hpp"
#include "tests/arch_layer/checks_xsimd.hpp"

namespace reproject::test {
namespace {

template <class Arch, class Fma>
ArchLayerChecks make_arch_layer_checks() {
  ArchLayerChecks c{};
  c.vmadd = check_vmadd<Arch, Fma>;
  c.vdiv = check_vdiv<Arch>;
  c.vfloor = check_vfloor<Arch>;
  c.vmin = check_vmin<Arch>;
  c.vmax = check_vmax<Arch>;
  c.round_to_int = check_round_to_int<Arch>;
  c.bits_of = check_bits_of<Arch>;
  c.float_bits = check_float_bits<Arch>;
  c.byte_lanes = check_byte_lanes<Arch>;
  c.gather = check_gather<Arch>;
  c.index_for_gather = check_index_for_gather<Arch>;
  c.lane_extreme = check_lane_extreme<Arch>;
  c.first_lane = check_first_lane<Arch>;
  c.shift_in_first = check_shift_in_first<Arch>;
  c.permute = check_permutes<Arch, false>;
  c.permute_two_registers = check_permutes<Arch, true>;
  c.store_first_lanes = check_store_first_lanes<Arch>;
  c.store_bytes = check_store_bytes<Arch>;
  c.load_u16 = check_load_u16<Arch>;
  c.store_u16 = check_store_u16<Arch>;
  c.pixel4 = check_pixel4<Arch>;
  c.lerp4 = check_lerp4<Arch, Fma>;
  c.blend_rgba8_q15 = check_blend_rgba8_q15<Arch>;
  c.srgb_far_pairs = check_srgb_far_pairs<Arch>;
  c.srgb_decode = check_srgb_decode<Arch>;
  c.srgb_encode = check_srgb_encode<Arch, Fma>;
  c.srgb_blend = check_srgb_blend<Arch, Fma>;
  c.load_half4 = check_load_half4<Arch>;
  c.store_half4 = check_store_half4<Arch>;
  c.xsimd_select = check_xsimd_select<Arch>;
  c.xsimd_compare = check_xsimd_compare<Arch>;
  c.xsimd_masks = check_xsimd_masks<Arch>;
  c.xsimd_convert = check_xsimd_convert<Arch>;
  c.xsimd_integer = check_xsimd_integer<Arch>;
  c.xsimd_arithmetic = check_xsimd_arithmetic<Arch>;
  return c;
}

}  // namespace
}  // namespace reproject::test
