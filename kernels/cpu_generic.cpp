// CPU detection for a processor the library has no SIMD code for, or a build without SIMD
// (REPROJECT_SIMD=OFF): only the scalar references run (kernels/cpu.hpp).
#include "kernels/cpu.hpp"

namespace reproject::detail {

bool cpu_supports(Arch arch) noexcept { return arch == Arch::scalar; }

}  // namespace reproject::detail
