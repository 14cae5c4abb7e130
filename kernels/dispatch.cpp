// The kernel tables of the instruction sets: a set compiled into this build returns its table
// (kernels/arch_<set>.cpp), any other null (kernels/arch_absent.cpp).
#include "kernels/dispatch.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>

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

// The lookup REPROJECT_SRGB_LOOKUP names; none when it is unset, empty or unknown.
std::optional<SrgbLookup> srgb_lookup_from_environment() {
  const char* value = std::getenv("REPROJECT_SRGB_LOOKUP");
  if (value == nullptr || *value == '\0') return std::nullopt;
  if (std::strcmp(value, "gathers") == 0) return SrgbLookup::gathers;
  if (std::strcmp(value, "permutes") == 0) return SrgbLookup::permutes;
  std::fprintf(stderr, "reproject: REPROJECT_SRGB_LOOKUP='%s' is not one of gathers, permutes; ignored\n", value);
  return std::nullopt;
}

}  // namespace

SrgbLookup srgb_lookup_for(const KernelTable& kernels) {
  // Read first, once: an unknown value is said on any set.
  static const std::optional<SrgbLookup> named = srgb_lookup_from_environment();
  if (kernels.srgb_lookup == nullptr) return SrgbLookup::gathers;
  return named ? *named : kernels.srgb_lookup();
}

const KernelTable& reference_kernels(Arch arch) { return scalar_kernels(arch != Arch::sse); }

}  // namespace reproject::detail
