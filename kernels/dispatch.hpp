// Internal: the kernel tables of each compiled instruction set.
#pragma once

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {

// Each is defined in its own translation unit built with that instruction set's flags; a
// null table means the set was not compiled in.
const KernelTable* sse_kernels();
const KernelTable* avx2_kernels();
const KernelTable* avx512_kernels();

#if defined(REPROJECT_HAVE_SCALAR_HOST)
// The scalar references compiled with AVX2 + FMA flags (frame.hpp, CMakeLists.txt).
namespace host {
const KernelTable& scalar_kernels(bool fused);
}
#endif

// The table for an instruction set, or null when it was not compiled in (ignores the CPU). For
// Arch::scalar: the AVX2 + FMA build of the scalar references on CPUs that have both.
const KernelTable* compiled_kernels(Arch arch);

// The scalar reference an instruction set must match bit for bit: the baseline build with its
// FMA policy.
const KernelTable& reference_kernels(Arch arch);

// reproject() with explicit kernels (for the tests that hold SIMD to its scalar reference);
// validates like reproject() and ignores Options::arch.
Status reproject_with(const KernelTable& kernels, const SourceView& source, const DepthDecoder& decoder,
                      const ParallaxModel& model, const Options& options, const TargetView& target);

}  // namespace detail
}  // namespace reproject
