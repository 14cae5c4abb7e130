// Advanced SIMD on AArch64 (xsimd's neon64, 4 float lanes) with the fused policy (vfmaq_f32).
// Needs no flags: every AArch64 processor has it.
#include "kernels/dispatch.hpp"
#include "kernels/simd_table.hpp"

namespace reproject::detail {

const KernelTable* neon_kernels() {
  static const KernelTable table = make_simd_table<Arch::neon>("neon");
  return &table;
}

}  // namespace reproject::detail
