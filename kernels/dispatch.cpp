// The kernel tables of the instruction sets compiled into this build (CMake defines
// REPROJECT_HAVE_<SET> for each arch translation unit it compiles, kernels/arch_<set>.cpp).
#include "kernels/dispatch.hpp"

#include "kernels/cpu.hpp"

namespace reproject {
namespace detail {

const KernelTable* compiled_kernels(Arch arch) {
  switch (arch) {
    case Arch::scalar:
#if defined(REPROJECT_HAVE_SCALAR_HOST)
      if (cpu_supports(Arch::avx2)) return &host::scalar_kernels(true);
#endif
      return &scalar_kernels(true);
    case Arch::sse:
#if defined(REPROJECT_HAVE_SSE)
      return sse_kernels();
#else
      return nullptr;
#endif
    case Arch::avx2:
#if defined(REPROJECT_HAVE_AVX2)
      return avx2_kernels();
#else
      return nullptr;
#endif
    case Arch::avx512:
#if defined(REPROJECT_HAVE_AVX512)
      return avx512_kernels();
#else
      return nullptr;
#endif
    case Arch::neon:
#if defined(REPROJECT_HAVE_NEON)
      return neon_kernels();
#else
      return nullptr;
#endif
  }
  return nullptr;
}

const KernelTable& reference_kernels(Arch arch) { return scalar_kernels(arch != Arch::sse); }

}  // namespace detail
}  // namespace reproject
