// The x86 family's CPU detection (kernels/cpu.hpp). xsimd 8.1 checks CPUID but not whether the
// operating system saves the wide registers, so XGETBV is read here too.
#include "kernels/cpu.hpp"

#include <cpuid.h>

namespace reproject::detail {
namespace {

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

// GCC's and Clang's <cpuid.h>; MSVC would use __cpuid/__cpuidex and _xgetbv from <intrin.h>.
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

}  // namespace

bool cpu_supports(Arch arch) noexcept {
  static const CpuFeatures cpu = detect();
  switch (arch) {
    case Arch::scalar: return true;
    case Arch::sse: return cpu.sse41;
    case Arch::avx2: return cpu.avx2_fma;
    case Arch::avx512: return cpu.avx512;
    case Arch::neon: return false;
  }
  return false;
}

}  // namespace reproject::detail
