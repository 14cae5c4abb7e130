// AVX2 with FMA3 (xsimd's fma3<avx2>: plain avx2 would turn xsimd::fma into multiply + add).
// Built with -mavx2 -mfma only.
#include "kernels/dispatch.hpp"
#include "kernels/simd_table.hpp"

namespace reproject::detail {

const KernelTable* avx2_kernels() {
  static const KernelTable table = make_simd_table<Arch::avx2>("avx2");
  return &table;
}

}  // namespace reproject::detail
