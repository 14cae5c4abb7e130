// The kernel tables of the instruction sets: a set compiled into this build returns its table
// (kernels/arch_<set>.cpp), any other null (kernels/arch_absent.cpp).
#include "kernels/dispatch.hpp"

#include "kernels/cpu.hpp"

namespace reproject::detail {

const KernelTable* compiled_kernels(Arch arch) {
  switch (arch) {
    case Arch::scalar:
#if defined(REPROJECT_HAVE_SCALAR_HOST)
      if (cpu_supports(Arch::avx2)) return &host::scalar_kernels(true);
#endif
      return &scalar_kernels(true);
    case Arch::sse: return sse_kernels();
    case Arch::avx2: return avx2_kernels();
    case Arch::avx512: return avx512_kernels();
    case Arch::neon: return neon_kernels();
  }
  return nullptr;
}

const KernelTable& reference_kernels(Arch arch) { return scalar_kernels(arch != Arch::sse); }

}  // namespace reproject::detail
