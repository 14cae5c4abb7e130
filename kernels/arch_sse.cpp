// The SSE4.1 baseline (no FMA instructions: the unfused policy). Built with -msse4.1 only.
#include "kernels/dispatch.hpp"
#include "kernels/simd_table.hpp"

namespace reproject::detail {

const KernelTable* sse_kernels() {
  static const KernelTable table = make_simd_table<Arch::sse>("sse");
  return &table;
}

}  // namespace reproject::detail
