// Internal: what src/reproject.cpp offers beside the public API, for the tests and fuzzers that
// hold every instruction set to its scalar reference. Not installed.
#pragma once

#include "kernels/kernel_table.hpp"
#include "reproject/reproject.hpp"

namespace reproject {
namespace detail {

// reproject() with explicit kernels (kernels/dispatch.hpp: compiled_kernels, reference_kernels);
// validates like reproject() and ignores Options::arch. `srgb_lookup`, when given, replaces the
// one kernels/dispatch.hpp's srgb_lookup_for() would choose (for tables that have it).
Status reproject_with(const KernelTable& kernels, const SourceView& source, const DepthDecoder& decoder,
                      const ParallaxModel& model, const Options& options, const TargetView& target,
                      const SrgbLookup* srgb_lookup = nullptr);

}  // namespace detail
}  // namespace reproject
