// Test-only objects compiled once per instruction set with that set's flags (tests/arch_layer/
// set.cpp; tests/CMakeLists.txt): the arch layer's checks, and a copy of the set's kernel table
// that counts the resolve's column-fetch modes. The library's own tables count nothing
// (kernels/simd.hpp, NoFetchTally).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "kernels/kernel_table.hpp"
#include "reproject/reproject.hpp"

namespace reproject::test {

// What one primitive's check found on one set.
struct Outcome {
  std::string not_applicable;  // why the set has no such primitive (empty: it was checked)
  long lanes = 0;              // lanes (or bytes) compared with the contract
  long failed = 0;
  std::vector<std::string> messages;  // the first failures, each naming lane, inputs, expected, got
  void fail(const std::string& message) {
    ++failed;
    if (messages.size() < 12) messages.push_back(message);
  }
};
using PrimitiveCheck = Outcome (*)();

// Every primitive of kernels/arch_layer.hpp, and the xsimd operations the twins use directly.
struct ArchLayerChecks {
  PrimitiveCheck vmadd, vdiv, vfloor, vmin, vmax, round_to_int, bits_of, float_bits, byte_lanes, gather,
      index_for_gather, lane_extreme, first_lane, shift_in_first, permute, permute_two_registers, store_first_lanes, store_bytes,
      load_u16, store_u16, pixel4, lerp4, blend_rgba8_q15, srgb_far_pairs, srgb_decode, srgb_encode, srgb_blend, load_half4, store_half4, xsimd_select, xsimd_compare, xsimd_masks,
      xsimd_convert, xsimd_integer, xsimd_arithmetic;
};

// Vectors the resolve read in each column-fetch mode (consecutive, shifted, spanning, gather), and
// rows it resolved on each colour path (kernels/resolve_row_simd.hpp ColorPath; set.cpp checks these
// two indices against it).
constexpr int kPathSrgbByGathers = 4, kPathSrgbByPermutes = 5;
struct FetchModeCounts {
  std::uint64_t vectors[4];
  std::uint64_t rows_by_path[6];
};
// The calling thread's counts for `set`. Defined in sets.cpp, compiled with the baseline flags: a
// thread_local defined in a set's translation unit may be aligned by clang for that set's 32- or
// 64-byte vector accesses, and Windows aligns a thread's TLS block to 16 bytes only (clang's MinGW
// build faulted on an aligned AVX load of it).
FetchModeCounts* fetch_mode_counts_of_thread(Arch set);
struct CountedTable {
  const detail::KernelTable* table;       // null: the set is not compiled in
  const FetchModeCounts* (*of_thread)();  // the calling thread's counts of this table
};

// Null / {null, null} for a set this build does not compile (another processor family, or
// REPROJECT_SIMD=OFF) and for Arch::scalar; counted_kernels also for every set when the counting
// tables are not compiled (fetch_counts_compiled() false).
const ArchLayerChecks* arch_layer_checks(Arch arch);
CountedTable counted_kernels(Arch arch);
// False in a build configured with -DREPROJECT_TEST_FETCH_COUNTS=OFF (some of CI's builds): the
// tests that read the counts run their other checks and say that they counted nothing.
bool fetch_counts_compiled();

}  // namespace reproject::test
