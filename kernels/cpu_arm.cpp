// The AArch64 family's CPU detection (kernels/cpu.hpp): Advanced SIMD (NEON) is part of every
// AArch64 processor, so there is nothing to ask the CPU.
#include "kernels/cpu.hpp"

namespace reproject::detail {

bool cpu_supports(Arch arch) noexcept { return arch == Arch::scalar || arch == Arch::neon; }

}  // namespace reproject::detail
