// AVX-512 (xsimd 8.1's avx512bw). Built with -mavx512f -mavx512cd -mavx512dq -mavx512bw -mfma only.
#include "kernels/dispatch.hpp"
#include "kernels/simd_table.hpp"

namespace reproject::detail {

const KernelTable* avx512_kernels() {
  static const KernelTable table = make_simd_table<Arch::avx512>("avx512");
  return &table;
}

}  // namespace reproject::detail
