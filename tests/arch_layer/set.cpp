// One instruction set's test objects (tests/arch_layer/sets.hpp), compiled once per set that CMake
// compiles for this processor, with that set's flags and REPROJECT_TEST_SET naming it (sse, avx2,
// avx512, neon): the arch layer's checks instantiated for the set's xsimd architecture and FMA
// policy, and the set's kernel table built once more with a tally that counts fetch modes. That
// second table is a whole copy of the set's kernels, left out when REPROJECT_TEST_FETCH_COUNTS is 0
// (the CMake option of that name: CI's sanitizer build, where this file was among the slowest to
// compile and the copy repeats kernels that the library's own tables run there anyway).
#include <cstdint>

#include "kernels/simd_table.hpp"
#include "tests/arch_layer/checks.hpp"
#include "tests/arch_layer/sets.hpp"

#ifndef REPROJECT_TEST_SET
#error "tests/CMakeLists.txt compiles this file with -DREPROJECT_TEST_SET=<set>"
#endif
#ifndef REPROJECT_TEST_FETCH_COUNTS
#error "tests/CMakeLists.txt compiles this file with -DREPROJECT_TEST_FETCH_COUNTS=0 or 1"
#endif
#define REPROJECT_TEST_CONCAT_(a, b) a##b
#define REPROJECT_TEST_CONCAT(a, b) REPROJECT_TEST_CONCAT_(a, b)
#define REPROJECT_TEST_STRING_(a) #a
#define REPROJECT_TEST_STRING(a) REPROJECT_TEST_STRING_(a)

namespace reproject::test {
namespace {

constexpr Arch kSet = Arch::REPROJECT_TEST_SET;
using SetArch = typename detail::InstructionSet<kSet>::arch;
using SetFma = typename detail::InstructionSet<kSet>::fma;

#if REPROJECT_TEST_FETCH_COUNTS
// The calling thread's counts of this set; each resolved row adds its own.
const FetchModeCounts* counts_of_thread() { return fetch_mode_counts_of_thread(kSet); }

static_assert(static_cast<int>(detail::ColorPath::rgba8_srgb) == kPathSrgbByGathers &&
              static_cast<int>(detail::ColorPath::rgba8_srgb_permutes) == kPathSrgbByPermutes);

struct CountingTally {
  std::uint64_t vectors[4] = {};
  int path = 0;
  void add(int mode) { ++vectors[mode]; }
  void row_path(int color_path) { path = color_path; }
  void end_row() {
    FetchModeCounts* counts = fetch_mode_counts_of_thread(kSet);
    for (int m = 0; m < 4; ++m) counts->vectors[m] += vectors[m];
    ++counts->rows_by_path[path];
  }
};
#endif

}  // namespace

const ArchLayerChecks* REPROJECT_TEST_CONCAT(arch_layer_checks_, REPROJECT_TEST_SET)() {
  static const ArchLayerChecks checks = make_arch_layer_checks<SetArch, SetFma>();
  return &checks;
}

#if REPROJECT_TEST_FETCH_COUNTS
CountedTable REPROJECT_TEST_CONCAT(counted_kernels_, REPROJECT_TEST_SET)() {
  static const detail::KernelTable table =
      detail::make_simd_table<kSet, CountingTally>(REPROJECT_TEST_STRING(REPROJECT_TEST_SET) " (counting)");
  return {&table, counts_of_thread};
}
#endif

}  // namespace reproject::test
