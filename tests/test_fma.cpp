// The fused multiply-add the scalar references use where the translation unit has no FMA
// instruction (kernels/fma.hpp, fma_in_software), against the hardware instruction, which IEEE 754
// requires to round once: random triples over the whole float range, products cancelled by the
// addend (where one rounding and two differ), values near float midpoints, and special values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "kernels/fma.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#include <immintrin.h>
#define REPROJECT_TEST_HARDWARE_FMA 1
__attribute__((target("fma"))) static float hardware_fma(float a, float b, float c) {
  return _mm_cvtss_f32(_mm_fmadd_ss(_mm_set_ss(a), _mm_set_ss(b), _mm_set_ss(c)));
}
static bool cpu_has_fma() {
  unsigned eax, ebx, ecx, edx;
  return __get_cpuid(1, &eax, &ebx, &ecx, &edx) && (ecx & bit_FMA) != 0;
}
#elif defined(__aarch64__)
#define REPROJECT_TEST_HARDWARE_FMA 1
static float hardware_fma(float a, float b, float c) { return std::fma(a, b, c); }  // fmadd
static bool cpu_has_fma() { return true; }
#endif

namespace {

std::uint32_t bits(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}
float of_bits(std::uint32_t b) {
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

TEST(FmaInSoftware, RoundsOnceAsTheInstructionDoes) {
#if defined(REPROJECT_TEST_HARDWARE_FMA)
  if (!cpu_has_fma()) GTEST_SKIP() << "this CPU has no FMA instruction to compare with";
  std::mt19937 rng(2026);
  long checked = 0, wrong = 0;
  auto check = [&](float a, float b, float c) {
    const float want = hardware_fma(a, b, c), got = reproject::detail::fma_in_software(a, b, c);
    ++checked;
    // NaN results: any NaN (which one is the instruction's choice, not a rounding matter).
    if (std::isnan(want) ? std::isnan(got) : bits(want) == bits(got)) return;
    if (++wrong <= 10) {
      ADD_FAILURE() << "fma(" << a << ", " << b << ", " << c << ") = " << got << " (0x" << std::hex << bits(got)
                    << "), one rounding gives " << want << " (0x" << bits(want) << ")" << std::dec;
    }
  };
  const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::min(), std::numeric_limits<float>::max(),
                            -std::numeric_limits<float>::max(), 0.5f, 3.0f, 1e-30f, 1e30f};
  for (float a : specials)
    for (float b : specials)
      for (float c : specials) check(a, b, c);
  std::uniform_real_distribution<float> unit(0.5f, 2.0f);
  std::uniform_int_distribution<int> nudge(-4, 4);
  for (int k = 0; k < 2000000; ++k) {
    // Any bits (NaNs and infinities included).
    check(of_bits(rng()), of_bits(rng()), of_bits(rng()));
    // Ordinary magnitudes, the addend cancelling the product's rounded value: the result is the
    // product's rounding error, which two roundings lose.
    const float a = unit(rng), b = unit(rng);
    const float rounded = a * b;
    check(a, b, -rounded);
    check(a, b, -of_bits(bits(rounded) + static_cast<std::uint32_t>(nudge(rng))));
    // Near a midpoint between two floats: the addend a tiny fraction of the product.
    check(a, b, std::ldexp(unit(rng), -24 - (k % 40)));
    // Results in the denormal range.
    check(std::ldexp(a, -70), std::ldexp(b, -70), std::ldexp(unit(rng), -140 - (k % 10)) * (k % 2 ? 1.0f : -1.0f));
  }
  std::printf("fma_in_software: %ld triples, %ld differ from the FMA instruction\n", checked, wrong);
  EXPECT_EQ(wrong, 0);
#else
  GTEST_SKIP() << "no FMA instruction to compare with on this processor family";
#endif
}

}  // namespace
