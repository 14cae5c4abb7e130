// Each set's test objects (tests/arch_layer/set.cpp) by Arch; tests/CMakeLists.txt defines
// REPROJECT_TEST_SET_<set> here for every set it compiled, and REPROJECT_TEST_FETCH_COUNTS to 1
// when set.cpp holds the counting tables too (the option of the same name), 0 when it does not.
#include "tests/arch_layer/sets.hpp"

namespace reproject::test {

#define REPROJECT_TEST_DECLARE_SET(set)              \
  const ArchLayerChecks* arch_layer_checks_##set(); \
  CountedTable counted_kernels_##set();
REPROJECT_TEST_DECLARE_SET(sse)
REPROJECT_TEST_DECLARE_SET(avx2)
REPROJECT_TEST_DECLARE_SET(avx512)
REPROJECT_TEST_DECLARE_SET(neon)

namespace {

struct SetObjects {
  const ArchLayerChecks* checks = nullptr;
  CountedTable counted{nullptr, nullptr};
};

#ifndef REPROJECT_TEST_FETCH_COUNTS
#error "tests/CMakeLists.txt compiles this file with -DREPROJECT_TEST_FETCH_COUNTS=0 or 1"
#elif REPROJECT_TEST_FETCH_COUNTS
#define REPROJECT_TEST_COUNTED(set) counted_kernels_##set()
#else  // no counting tables: {null, null}, as for a set that is not compiled in
#define REPROJECT_TEST_COUNTED(set) CountedTable{}
#endif

SetObjects objects_of(Arch arch) {
  switch (arch) {
#if defined(REPROJECT_TEST_SET_sse)
    case Arch::sse: return {arch_layer_checks_sse(), REPROJECT_TEST_COUNTED(sse)};
#endif
#if defined(REPROJECT_TEST_SET_avx2)
    case Arch::avx2: return {arch_layer_checks_avx2(), REPROJECT_TEST_COUNTED(avx2)};
#endif
#if defined(REPROJECT_TEST_SET_avx512)
    case Arch::avx512: return {arch_layer_checks_avx512(), REPROJECT_TEST_COUNTED(avx512)};
#endif
#if defined(REPROJECT_TEST_SET_neon)
    case Arch::neon: return {arch_layer_checks_neon(), REPROJECT_TEST_COUNTED(neon)};
#endif
    default: break;
  }
  return {};
}

}  // namespace

FetchModeCounts* fetch_mode_counts_of_thread(Arch set) {
  thread_local FetchModeCounts counts[kArchCount] = {};
  return &counts[static_cast<int>(set)];
}

const ArchLayerChecks* arch_layer_checks(Arch arch) { return objects_of(arch).checks; }
CountedTable counted_kernels(Arch arch) { return objects_of(arch).counted; }
bool fetch_counts_compiled() { return REPROJECT_TEST_FETCH_COUNTS != 0; }

}  // namespace reproject::test
