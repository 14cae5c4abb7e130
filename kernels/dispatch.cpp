// Which instruction set runs: the best one the CPU *and* the operating system support, chosen
// once, unless REPROJECT_FORCE_ARCH names another supported one. xsimd 8.1 checks CPUID but not
// whether the OS saves the wide registers, so XGETBV is checked here.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "kernels/dispatch.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

namespace reproject {
namespace {

const char* const kArchNames[kArchCount] = {"scalar", "sse", "avx2", "avx512"};

#if defined(__x86_64__) || defined(__i386__)
unsigned long long xgetbv0() {
  unsigned eax, edx;
  __asm__ volatile("xgetbv" : "=a"(eax), "=d"(edx) : "c"(0));
  return (static_cast<unsigned long long>(edx) << 32) | eax;
}

struct CpuFeatures {
  bool sse41 = false;
  bool avx2_fma = false;
  bool avx512 = false;
};

CpuFeatures detect() {
  CpuFeatures cpu;
  unsigned a, b, c, d;
  if (!__get_cpuid(1, &a, &b, &c, &d)) return cpu;
  cpu.sse41 = (c & bit_SSE4_1) != 0;
  const bool osxsave = (c & bit_OSXSAVE) != 0;
  const bool fma = (c & bit_FMA) != 0;
  const bool f16c = (c & bit_F16C) != 0;  // rgba16f's conversions (every AVX2 CPU has it)
  if (!osxsave) return cpu;
  const unsigned long long xcr0 = xgetbv0();
  const bool os_ymm = (xcr0 & 0x6) == 0x6;        // SSE and AVX state
  const bool os_zmm = (xcr0 & 0xe6) == 0xe6;      // plus opmask and both ZMM halves
  if (!__get_cpuid_count(7, 0, &a, &b, &c, &d)) return cpu;
  cpu.avx2_fma = os_ymm && fma && f16c && (b & bit_AVX2) != 0;
  cpu.avx512 = cpu.avx2_fma && os_zmm && (b & bit_AVX512F) && (b & bit_AVX512CD) && (b & bit_AVX512DQ) &&
               (b & bit_AVX512BW);
  return cpu;
}
#endif

bool cpu_supports(Arch arch) {
#if defined(__x86_64__) || defined(__i386__)
  static const CpuFeatures cpu = detect();
  switch (arch) {
    case Arch::scalar: return true;
    case Arch::sse: return cpu.sse41;
    case Arch::avx2: return cpu.avx2_fma;
    case Arch::avx512: return cpu.avx512;
  }
  return false;
#else
  return arch == Arch::scalar;
#endif
}

Arch best_supported() {
  for (Arch arch : {Arch::avx512, Arch::avx2, Arch::sse}) {
    if (arch_supported(arch)) return arch;
  }
  return Arch::scalar;
}

// Runs once per process. A forced set that is unknown or that this CPU cannot run is said on
// stderr (once), so that nobody reads a run as covering a set it did not execute.
Arch choose() {
  const Arch best = best_supported();
  const char* forced = std::getenv("REPROJECT_FORCE_ARCH");
  if (forced != nullptr && *forced != '\0') {  // set and not empty (empty: as if unset)
    Arch arch;
    if (!parse_arch(forced, &arch)) {
      std::fprintf(stderr, "reproject: REPROJECT_FORCE_ARCH='%s' is not one of scalar, sse, avx2, avx512; using %s\n",
                   forced, to_string(best));
    } else if (!arch_supported(arch)) {
      std::fprintf(stderr, "reproject: REPROJECT_FORCE_ARCH=%s is not supported by this CPU; using %s\n", forced,
                   to_string(best));
    } else {
      return arch;
    }
  }
  return best;
}

}  // namespace

const char* to_string(Arch arch) noexcept {
  const unsigned index = static_cast<unsigned>(arch);
  return index < static_cast<unsigned>(kArchCount) ? kArchNames[index] : "unknown";
}

bool parse_arch(const char* name, Arch* out) noexcept {
  if (name == nullptr) return false;
  for (int i = 0; i < kArchCount; ++i) {
    if (std::strcmp(name, kArchNames[i]) == 0) {
      if (out) *out = static_cast<Arch>(i);
      return true;
    }
  }
  return false;
}

bool arch_supported(Arch arch) noexcept {
  // The CPU first: compiled_kernels() runs code of the set's own translation unit (its table's
  // initialiser), which the compiler may build with that set's instructions (SIGILL otherwise).
  return cpu_supports(arch) && detail::compiled_kernels(arch) != nullptr;
}

Arch selected_arch() noexcept {
  static const Arch arch = choose();
  return arch;
}

namespace detail {

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
  }
  return nullptr;
}

const KernelTable& reference_kernels(Arch arch) { return scalar_kernels(arch != Arch::sse); }

}  // namespace detail
}  // namespace reproject
