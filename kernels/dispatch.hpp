// Internal: the kernel tables of each compiled instruction set.
#pragma once

#include "kernels/kernel_table.hpp"

namespace reproject::detail {

// Each is defined in its own translation unit built with that instruction set's flags
// (kernels/arch_<set>.cpp) when CMake compiles the set for the target processor, and returns
// null otherwise (kernels/arch_absent.cpp).
const KernelTable* sse_kernels();
const KernelTable* avx2_kernels();
const KernelTable* avx512_kernels();
const KernelTable* neon_kernels();

#if defined(REPROJECT_HAVE_SCALAR_HOST)
// The scalar references compiled with AVX2 + FMA flags (kernels/kernel_table.hpp, CMakeLists.txt).
namespace host {
const KernelTable& scalar_kernels(bool fused);
}
#endif

// The table for an instruction set, or null when it was not compiled in (ignores the CPU:
// kernels/cpu.hpp says what it supports). For Arch::scalar: the AVX2 + FMA build of the scalar
// references on CPUs that have both.
const KernelTable* compiled_kernels(Arch arch);

// How `kernels` reads the sRGB tables of rgba8_srgb frames, for a table with two ways
// (KernelTable::srgb_lookup; gathers for any other): the environment variable
// REPROJECT_SRGB_LOOKUP (`gathers` or `permutes`) when set and not empty, else the faster on this
// processor (timed once). The variable is read at the first call, whatever the table; an unknown
// value is said once on stderr and ignored. The same bytes either way: it only moves time.
SrgbLookup srgb_lookup_for(const KernelTable& kernels);

// The scalar reference an instruction set must match bit for bit: the baseline build with its
// FMA policy.
const KernelTable& reference_kernels(Arch arch);

}  // namespace reproject::detail
