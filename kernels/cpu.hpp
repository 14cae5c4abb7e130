// Internal: which instruction sets this CPU and its operating system can run. One definition per
// processor family, chosen by CMake with the arch translation units: kernels/cpu_x86.cpp (CPUID
// and XGETBV), kernels/cpu_generic.cpp (scalar only, for processors without SIMD code here).
#pragma once

#include "reproject/reproject.hpp"

namespace reproject::detail {

// Whether the CPU and the operating system support `arch` (whether it was compiled in is
// kernels/dispatch.hpp's compiled_kernels()). Arch::scalar: always.
bool cpu_supports(Arch arch) noexcept;

}  // namespace reproject::detail
