// The kernel tables of the instruction sets: a set compiled into this build returns its table
// (kernels/arch_<set>.cpp), any other null (kernels/arch_absent.cpp).
#include "kernels/dispatch.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "kernels/color_formats.hpp"
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

namespace {

// REPROJECT_SRGB_LOOKUP, read once: 0 unset (or empty or unknown), 1 gathers, 2 permutes.
int srgb_lookup_from_environment() {
  const char* value = std::getenv("REPROJECT_SRGB_LOOKUP");
  if (value == nullptr || *value == '\0') return 0;
  if (std::strcmp(value, "gathers") == 0) return 1;
  if (std::strcmp(value, "permutes") == 0) return 2;
  std::fprintf(stderr, "reproject: REPROJECT_SRGB_LOOKUP='%s' is not one of gathers, permutes; ignored\n", value);
  return 0;
}

}  // namespace

SrgbLookup srgb_lookup_for(const KernelTable& kernels) {
  static const int forced = srgb_lookup_from_environment();  // first: an unknown value is said on any set
  if (kernels.srgb_lookup == nullptr) return SrgbLookup::gathers;
  if (forced != 0) return forced == 2 ? SrgbLookup::permutes : SrgbLookup::gathers;
  return kernels.srgb_lookup();
}

const KernelTable& reference_kernels(Arch arch) { return scalar_kernels(arch != Arch::sse); }

}  // namespace reproject::detail
