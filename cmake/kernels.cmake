# The kernels' instruction sets, chosen from the processor the compiler targets (included by the
# top-level CMakeLists.txt after the `reproject` target exists).
#
# One translation unit per instruction set (kernels/arch_<set>.cpp), with that set's flags on that
# file only; the API, the dispatch and the scalar references are built with the baseline flags.
# Each is an object library of its own so that tests/check_object_code.cmake can read its object
# code. A set this family does not have gets a null table (kernels/arch_absent.cpp), so that
# kernels/dispatch.cpp names every set alike; the family's CPU detection is kernels/cpu_<family>.cpp.
#
# The family comes from the compiler's own predefined macros rather than CMAKE_SYSTEM_PROCESSOR,
# which is spelled aarch64 (Linux, Android), arm64 (Apple) or ARM64 (Windows), x86_64, AMD64 or
# amd64, and which a user's toolchain may leave at the host's value. No -m flag reaches a compiler
# for another processor.
include(CheckCXXSymbolExists)
check_cxx_symbol_exists(__x86_64__ "" REPROJECT_TARGET_X86_64)
if(NOT REPROJECT_TARGET_X86_64)
  check_cxx_symbol_exists(_M_X64 "" REPROJECT_TARGET_X86_64_MSVC)
endif()
check_cxx_symbol_exists(__aarch64__ "" REPROJECT_TARGET_AARCH64)
if(NOT REPROJECT_TARGET_AARCH64)
  check_cxx_symbol_exists(_M_ARM64 "" REPROJECT_TARGET_AARCH64_MSVC)
endif()

set(REPROJECT_SIMD_SETS "")
if(NOT REPROJECT_SIMD)
  set(REPROJECT_CPU_FAMILY generic)
  message(STATUS "reproject kernels: scalar references only (REPROJECT_SIMD=OFF)")
elseif(REPROJECT_TARGET_X86_64 OR REPROJECT_TARGET_X86_64_MSVC)
  set(REPROJECT_CPU_FAMILY x86)
  set(REPROJECT_SIMD_SETS sse avx2 avx512)
elseif(REPROJECT_TARGET_AARCH64 OR REPROJECT_TARGET_AARCH64_MSVC)
  set(REPROJECT_CPU_FAMILY arm)
  set(REPROJECT_SIMD_SETS neon)
else()
  set(REPROJECT_CPU_FAMILY generic)
  message(STATUS "reproject kernels: no SIMD code for this processor (${CMAKE_SYSTEM_PROCESSOR}); scalar references only")
endif()
if(REPROJECT_SIMD_SETS)
  message(STATUS "reproject kernels: scalar references + ${REPROJECT_SIMD_SETS}")
endif()
target_sources(reproject PRIVATE ${PROJECT_SOURCE_DIR}/kernels/cpu_${REPROJECT_CPU_FAMILY}.cpp)

# Flags per set. NEON needs none: every AArch64 processor has Advanced SIMD.
if(MSVC)
  # MSVC (and clang-cl): /arch:AVX2 brings FMA3 and F16C, /arch:AVX512 F, CD, DQ, BW and VL. There
  # is no SSE4.1 switch: MSVC emits any SSE intrinsic without one, and xsimd 8 turns its SSE4.1 code
  # on for every x64 MSVC build (xsimd/config/xsimd_config.hpp), so the sse table is built with the
  # baseline flags, and only its own code uses SSE4.1, as with -msse4.1.
  set(REPROJECT_FLAGS_sse "")
  set(REPROJECT_FLAGS_avx2 /arch:AVX2)
  set(REPROJECT_FLAGS_avx512 /arch:AVX512)
else()
  set(REPROJECT_FLAGS_sse -msse4.1)
  set(REPROJECT_FLAGS_avx2 -mavx2 -mfma -mf16c)
  set(REPROJECT_FLAGS_avx512 -mavx512f -mavx512cd -mavx512dq -mavx512bw -mavx2 -mfma -mf16c)
endif()
set(REPROJECT_FLAGS_neon "")
# AddressSanitizer with GCC (CI's sanitizer build): the SIMD sets without its use-after-scope checks,
# which instrument the scope of every inlined vector temporary of the kernels: arch_avx512.cpp took
# 152 s to compile at -O1 with ASan and UBSan, 30 s without these checks (and the arch-layer tests'
# copies of the sets, which take these options, alike). Every other check stays on in these files
# (heap and stack overflow, use after free, UBSan), and use-after-scope everywhere else; the
# kernels' locals are vectors and fixed arrays used within the block that declares them.
set(REPROJECT_SANITIZER_FLAGS_SIMD "")
if(REPROJECT_ADDRESS_SANITIZER AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set(REPROJECT_SANITIZER_FLAGS_SIMD -fno-sanitize-address-use-after-scope)
endif()
get_target_property(REPROJECT_XSIMD_INCLUDE xsimd INTERFACE_INCLUDE_DIRECTORIES)
foreach(set IN LISTS REPROJECT_SIMD_SETS)
  add_library(reproject_simd_${set} OBJECT kernels/arch_${set}.cpp)
  target_include_directories(reproject_simd_${set} PRIVATE ${PROJECT_SOURCE_DIR}/include ${PROJECT_SOURCE_DIR})
  target_include_directories(reproject_simd_${set} SYSTEM PRIVATE ${REPROJECT_XSIMD_INCLUDE})
  target_link_libraries(reproject_simd_${set} PRIVATE reproject_flags)
  set_target_properties(reproject_simd_${set} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_compile_options(reproject_simd_${set} PRIVATE ${REPROJECT_FLAGS_${set}} ${REPROJECT_SANITIZER_FLAGS_SIMD})
  target_sources(reproject PRIVATE $<TARGET_OBJECTS:reproject_simd_${set}>)
endforeach()
# The sets of the other families (or all, without SIMD): tables that are null.
foreach(set sse avx2 avx512 neon)
  if(NOT set IN_LIST REPROJECT_SIMD_SETS)
    add_library(reproject_absent_${set} OBJECT kernels/arch_absent.cpp)
    target_compile_definitions(reproject_absent_${set} PRIVATE REPROJECT_ABSENT_TABLE=${set}_kernels)
    target_include_directories(reproject_absent_${set} PRIVATE ${PROJECT_SOURCE_DIR}/include ${PROJECT_SOURCE_DIR})
    target_link_libraries(reproject_absent_${set} PRIVATE reproject_flags)
    set_target_properties(reproject_absent_${set} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_sources(reproject PRIVATE $<TARGET_OBJECTS:reproject_absent_${set}>)
  endif()
endforeach()
if(TARGET reproject_simd_avx512 AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # GCC 12 reports its own avx512fintrin.h mask helpers as maybe-uninitialized when inlined
  # through xsimd; a false positive inside the compiler's header.
  target_compile_options(reproject_simd_avx512 PRIVATE -Wno-maybe-uninitialized -Wno-uninitialized)
endif()
# x86 only: the scalar references once more, with AVX2 + FMA flags, into namespace detail::host
# (kernels/kernel_table.hpp). Arch::scalar runs this copy on CPUs that have them, so that the
# benchmarks' scalar baseline is what a user's own scalar code built with -march=native would be,
# not one that calls libm for every fma and floor. Auto-vectorisation is left as -O3 does it.
# (On AArch64 the baseline already has fmadd and frintm: one copy serves.)
set(REPROJECT_SCALAR_SOURCES kernels/decode.cpp kernels/resolve.cpp kernels/scanline.cpp kernels/march16.cpp
    kernels/single.cpp kernels/secant.cpp kernels/exact.cpp kernels/scalar_table.cpp)
if(REPROJECT_CPU_FAMILY STREQUAL "x86")
  add_library(reproject_scalar_host OBJECT ${REPROJECT_SCALAR_SOURCES})
  target_compile_definitions(reproject_scalar_host PRIVATE REPROJECT_SCALAR_COPY=host)
  if(MSVC)
    target_compile_options(reproject_scalar_host PRIVATE /arch:AVX2)  # AVX2 brings FMA3 in MSVC
  else()
    target_compile_options(reproject_scalar_host PRIVATE -mavx2 -mfma)
  endif()
  target_include_directories(reproject_scalar_host PRIVATE ${PROJECT_SOURCE_DIR}/include ${PROJECT_SOURCE_DIR})
  target_link_libraries(reproject_scalar_host PRIVATE reproject_flags)
  set_target_properties(reproject_scalar_host PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_sources(reproject PRIVATE $<TARGET_OBJECTS:reproject_scalar_host>)
  target_compile_definitions(reproject PRIVATE REPROJECT_HAVE_SCALAR_HOST=1)
  # The AVX2 and AVX-512 tables call scalar pieces too (tails, secant's tile plan): the host copy.
  target_compile_definitions(reproject_simd_avx2 PRIVATE REPROJECT_SCALAR_COPY=host)
  target_compile_definitions(reproject_simd_avx512 PRIVATE REPROJECT_SCALAR_COPY=host)
endif()
