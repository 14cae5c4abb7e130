# ctest ObjectCode.<name>: reads one kernel object's machine code, so that a defect of an
# instruction set this CPU cannot run still fails here (the AVX-512 table once lost its FMAs to a
# generic xsimd fallback and nobody's machine could run it).
#   cmake -DOBJDUMP=<objdump> -DOBJECTS=<a.o|b.o|...> -DEXPECT=<policy> -P check_object_code.cmake
# EXPECT (over the objects together):
#   zmm | ymm | xmm  fused: at least one FMA on registers of that width, and no call into libm;
#                    zmm and ymm: rgba16f's conversions by F16C (vcvtph2ps, vcvtps2ph);
#   unfused          no FMA of any width, no F16C instruction (the SSE set runs on CPUs without
#                    it: rgba16f converts in software there), and no call into libm.
#   neon             AArch64, fused: at least one vector FMA (fmla/fmls on .4s), IEEE vector
#                    division (fdiv on .4s) and no reciprocal estimate (xsimd 8.1's neon64 float
#                    division is one), rgba16f's conversions by FCVTL/FCVTN, table look-ups
#                    (tbl/tbx) in the column fetch that reads every format's pixels, no call into
#                    libm and none into xsimd at all (its neon wrappers are out of line there).
# Every policy: no out-of-line call into one of xsimd's generic fallbacks (a kernel of the
# `generic` architecture, which the compiler did not inline), and no thread-local access
# (fs-relative on x86, tpidr_el0 on AArch64): the kernels keep no per-thread state, and test
# counters stay in the tests' own copies of the tables (kernels/simd.hpp, NoFetchTally).
cmake_policy(SET CMP0007 NEW)
foreach(var OBJDUMP OBJECTS EXPECT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_object_code.cmake needs -D${var}=...")
  endif()
endforeach()
string(REPLACE "|" ";" objects "${OBJECTS}")
set(listing "")
set(names "")
foreach(object IN LISTS objects)
  execute_process(COMMAND "${OBJDUMP}" -dr --no-show-raw-insn "${object}"
    OUTPUT_VARIABLE one ERROR_VARIABLE errors RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${OBJDUMP} -dr ${object} failed (${result}): ${errors}")
  endif()
  string(APPEND listing "${one}")
  get_filename_component(one_name "${object}" NAME)
  list(APPEND names "${one_name}")
endforeach()

# Every fused multiply-add form, one line each: x86 (vfmadd, vfmsub, vfnmadd, vfnmsub, vfmaddsub,
# vfmsubadd; any operand order and element type); AArch64 (fmla, fmls on vectors; fmadd, fmsub,
# fnmadd, fnmsub on scalars).
if(EXPECT STREQUAL "neon")
  string(REGEX MATCHALL "[\t ](fml[as]|fn?m(add|sub))[\t ][^\n]*" fmas "${listing}")
else()
  string(REGEX MATCHALL "[\t ]vf(n?m(add|sub)|maddsub|msubadd)[0-9]*[sp][sd][^\n]*" fmas "${listing}")
endif()
list(LENGTH fmas fma_count)
set(width_count 0)
if(EXPECT STREQUAL "neon")
  set(width_pattern "v[0-9]+\\.4s")  # 4 floats: a whole NEON register
else()
  set(width_pattern "%${EXPECT}")
endif()
foreach(line IN LISTS fmas)
  if(line MATCHES "${width_pattern}")
    math(EXPR width_count "${width_count} + 1")
  endif()
endforeach()

# Calls into libm: a relocation against one of its functions (fmaf, floorf, ...), which would mean
# a rounding step done out of line, and differently on each machine's libm. (x86 relocations
# carry an addend, "floorf-0x4"; AArch64 ones end the line.)
set(call_relocations "R_X86_64_(PLT32|PC32|GOTPCREL|GOTPCRELX|REX_GOTPCRELX)|R_AARCH64_(CALL26|JUMP26|ADR_GOT_PAGE|LD64_GOT_LO12_NC)")
string(REGEX MATCHALL
  "(${call_relocations})[\t ]+(fma|floor|ceil|trunc|round|lround|llround|nearbyint|rint|lrint|llrint|sqrt|fmin|fmax|exp|exp2|log|log2|pow|copysign|ldexp|frexp|modf)f?(@[A-Za-z_.0-9]+)?[-+\n]"
  libm_calls "${listing}")
list(LENGTH libm_calls libm_count)

# Out-of-line calls into xsimd's generic kernels (the mangled name of a `requires_arch<generic>` kernel holds "7genericE").
string(REGEX MATCHALL "(${call_relocations})[\t ]+_ZN5xsimd[A-Za-z0-9_]*7genericE[^\n]*" generic_calls "${listing}")
list(LENGTH generic_calls generic_count)

# Hardware half-float conversions: F16C (x86), FCVTL/FCVTN on vectors (AArch64).
if(EXPECT STREQUAL "neon")
  string(REGEX MATCHALL "[\t ]fcvt[ln]2?[\t ]+v[^\n]*" halves "${listing}")
else()
  string(REGEX MATCHALL "[\t ]vcvt(ps2ph|ph2ps)[^\n]*" halves "${listing}")
endif()
list(LENGTH halves half_count)

# The rgba8 blend in fixed point (kernels/arch_layer.hpp blend_rgba8_q15): a multiply-high with
# rounding on 16-bit lanes, pmulhrsw on x86 (every set: SSSE3 has it), sqrdmulh on AArch64.
if(EXPECT STREQUAL "neon")
  string(REGEX MATCHALL "[\t ]sqrdmulh[\t ]+v[0-9]+\\.8h[^\n]*" mulhrs "${listing}")
else()
  string(REGEX MATCHALL "[\t ]v?pmulhrsw[\t ][^\n]*" mulhrs "${listing}")
endif()
list(LENGTH mulhrs mulhrs_count)

# Table look-ups (AArch64): the column fetch's permutes.
string(REGEX MATCHALL "[\t ]tb[lx][\t ][^\n]*" lookups "${listing}")
list(LENGTH lookups lookup_count)

# AArch64 division: vector fdiv, and the reciprocal estimates that an approximate one is built of.
string(REGEX MATCHALL "[\t ]fdiv[\t ]+v[0-9]+\\.4s[^\n]*" divisions "${listing}")
list(LENGTH divisions division_count)
string(REGEX MATCHALL "[\t ](frecpe|frecps|frsqrte|frsqrts)[\t ][^\n]*" estimates "${listing}")
list(LENGTH estimates estimate_count)
# Any out-of-line call into xsimd (AArch64: GCC leaves its neon wrappers out of line).
string(REGEX MATCHALL "(${call_relocations})[\t ]+_ZN5xsimd[^\n]*" xsimd_calls "${listing}")
list(LENGTH xsimd_calls xsimd_count)

# Thread-local storage: x86-64 reaches it through %fs, AArch64 through the thread pointer register.
string(REGEX MATCHALL "%fs:[^\n]*|tpidr_el0[^\n]*" tls_accesses "${listing}")
list(LENGTH tls_accesses tls_count)

string(REPLACE ";" ", " name "${names}")
if(libm_count GREATER 0)
  list(REMOVE_DUPLICATES libm_calls)
  string(REPLACE ";" "\n  " shown "${libm_calls}")
  message(FATAL_ERROR "${name}: ${libm_count} calls into libm (rounding done out of line):\n  ${shown}")
endif()
if(generic_count GREATER 0)
  list(REMOVE_DUPLICATES generic_calls)
  string(REPLACE ";" "\n  " shown "${generic_calls}")
  message(FATAL_ERROR "${name}: ${generic_count} calls into xsimd's generic fallbacks:\n  ${shown}")
endif()
if(NOT EXPECT STREQUAL "xmm" AND mulhrs_count EQUAL 0)
  message(FATAL_ERROR "${name}: no pmulhrsw/sqrdmulh: rgba8 is not blended in fixed point")
endif()
if(tls_count GREATER 0)
  list(GET tls_accesses 0 first)
  message(FATAL_ERROR "${name}: ${tls_count} thread-local accesses (first: ${first}): a counter or other per-thread "
                      "state in the kernels")
endif()
if(EXPECT STREQUAL "unfused")
  if(fma_count GREATER 0)
    list(GET fmas 0 first)
    message(FATAL_ERROR "${name}: built without FMA, yet holds ${fma_count} FMA instructions (first:${first})")
  endif()
  if(half_count GREATER 0)
    list(GET halves 0 first)
    message(FATAL_ERROR "${name}: the SSE set holds ${half_count} F16C instructions (first:${first})")
  endif()
  message(STATUS "${name}: no FMA, no libm call (policy unfused)")
elseif(EXPECT STREQUAL "zmm" OR EXPECT STREQUAL "ymm" OR EXPECT STREQUAL "xmm")
  if(width_count EQUAL 0)
    message(FATAL_ERROR "${name}: fused policy, but no FMA on ${EXPECT} registers (${fma_count} FMAs of other widths): "
                        "a vector multiply-add is being computed with two roundings")
  endif()
  if(NOT EXPECT STREQUAL "xmm" AND half_count EQUAL 0)
    message(FATAL_ERROR "${name}: no F16C conversion: rgba16f is converting in software on a set that has F16C")
  endif()
  message(STATUS "${name}: ${width_count} FMAs on ${EXPECT} registers (${fma_count} in all), ${half_count} F16C conversions, no libm call")
elseif(EXPECT STREQUAL "neon")
  if(width_count EQUAL 0)
    message(FATAL_ERROR "${name}: fused policy, but no vector FMA (fmla/fmls on .4s; ${fma_count} scalar ones): "
                        "a vector multiply-add is being computed with two roundings")
  endif()
  if(half_count EQUAL 0)
    message(FATAL_ERROR "${name}: no FCVTL/FCVTN: rgba16f is converting in software on a set that has hardware conversions")
  endif()
  if(lookup_count EQUAL 0)
    message(FATAL_ERROR "${name}: no table look-up (tbl/tbx): the column fetch gathers lane by lane instead of permuting")
  endif()
  if(division_count EQUAL 0 OR estimate_count GREATER 0)
    message(FATAL_ERROR "${name}: ${division_count} vector fdiv and ${estimate_count} reciprocal estimates: a vector "
                        "division is not correctly rounded (xsimd 8.1's neon64 division; the arch layer's vdiv is)")
  endif()
  if(xsimd_count GREATER 0)
    list(GET xsimd_calls 0 first)
    message(FATAL_ERROR "${name}: ${xsimd_count} out-of-line calls into xsimd (first: ${first})")
  endif()
  message(STATUS "${name}: ${width_count} vector FMAs (${fma_count} in all), ${division_count} vector divisions and no "
                 "reciprocal estimate, ${half_count} half conversions, ${lookup_count} table look-ups, no libm or xsimd call")
else()
  message(FATAL_ERROR "unknown EXPECT '${EXPECT}'")
endif()
