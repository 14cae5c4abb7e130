// The x86 family's CPU detection (kernels/cpu.hpp). xsimd 8.1 checks CPUID but not whether the
// operating system saves the wide registers, so XGETBV is read here too.
#include "kernels/cpu.hpp"

#if defined(_WIN32)
#include <intrin.h>  // MSVC's and MinGW-w64's: __cpuid, __cpuidex, _xgetbv
#else
#include <cpuid.h>
#endif

namespace reproject::detail {
namespace {

// CPUID leaf `leaf`, sub-leaf `subleaf`: {eax, ebx, ecx, edx}; all zero past the highest leaf.
struct Registers {
  unsigned r[4] = {0, 0, 0, 0};
};

#if defined(_WIN32)
Registers cpuid(int leaf, int subleaf) {
  int top[4];
  __cpuid(top, 0);
  Registers out;
  if (leaf > top[0]) return out;
  int regs[4];
  __cpuidex(regs, leaf, subleaf);
  for (int i = 0; i < 4; ++i) out.r[i] = static_cast<unsigned>(regs[i]);
  return out;
}

// GCC and Clang compile _xgetbv only in a function that targets XSAVE (MSVC needs nothing); the
// caller checked OSXSAVE first.
#if defined(__GNUC__)
__attribute__((target("xsave")))
#endif
unsigned long long xgetbv0() {
  return _xgetbv(0);
}
#else
Registers cpuid(unsigned leaf, unsigned subleaf) {
  Registers out;
  if (leaf > static_cast<unsigned>(__get_cpuid_max(0, nullptr))) return out;
  __cpuid_count(leaf, subleaf, out.r[0], out.r[1], out.r[2], out.r[3]);
  return out;
}

unsigned long long xgetbv0() {
  unsigned eax, edx;
  __asm__ volatile("xgetbv" : "=a"(eax), "=d"(edx) : "c"(0));
  return (static_cast<unsigned long long>(edx) << 32) | eax;
}
#endif

// The feature bits (Intel SDM vol. 2A, CPUID): leaf 1 ECX and leaf 7 EBX.
constexpr unsigned kSse41 = 1u << 19, kFma = 1u << 12, kOsxsave = 1u << 27, kF16c = 1u << 29;
constexpr unsigned kAvx2 = 1u << 5, kAvx512f = 1u << 16, kAvx512dq = 1u << 17, kAvx512cd = 1u << 28,
                   kAvx512bw = 1u << 30;

struct CpuFeatures {
  bool sse41 = false;
  bool avx2_fma = false;
  bool avx512 = false;
};

CpuFeatures detect() {
  CpuFeatures cpu;
  const unsigned c = cpuid(1, 0).r[2];
  cpu.sse41 = (c & kSse41) != 0;
  const bool fma = (c & kFma) != 0;
  const bool f16c = (c & kF16c) != 0;  // rgba16f's conversions (every AVX2 CPU has it)
  if ((c & kOsxsave) == 0) return cpu;
  const unsigned long long xcr0 = xgetbv0();
  const bool os_ymm = (xcr0 & 0x6) == 0x6;        // SSE and AVX state
  const bool os_zmm = (xcr0 & 0xe6) == 0xe6;      // plus opmask and both ZMM halves
  const unsigned b = cpuid(7, 0).r[1];
  cpu.avx2_fma = os_ymm && fma && f16c && (b & kAvx2) != 0;
  const unsigned avx512 = kAvx512f | kAvx512cd | kAvx512dq | kAvx512bw;
  cpu.avx512 = cpu.avx2_fma && os_zmm && (b & avx512) == avx512;
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
