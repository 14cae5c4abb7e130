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

// The table for an instruction set, or null when it was not compiled in (ignores the CPU).
const KernelTable* compiled_kernels(Arch arch);

// The scalar reference an instruction set must match bit for bit: the one with its FMA policy.
const KernelTable& reference_kernels(Arch arch);

// reproject() with explicit kernels (for the tests that hold SIMD to its scalar reference);
// validates like reproject() and ignores Options::arch.
Status reproject_with(const KernelTable& kernels, const SourceView& source, const DepthDecoder& decoder,
                      const ParallaxModel& model, const Options& options, const TargetView& target);

}  // namespace detail
}  // namespace reproject
