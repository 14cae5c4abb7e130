# ctest ObjectCode.<name>: reads one kernel object's machine code, so that a defect of an
# instruction set this CPU cannot run still fails here (the AVX-512 table once lost its FMAs to a
# generic xsimd fallback and nobody's machine could run it).
#   cmake -DOBJDUMP=<objdump> -DOBJECTS=<a.o|b.o|...> -DPOLICY=<policy> -P check_object_code.cmake
# EXPECT (over the objects together):
#   zmm | ymm | xmm  fused: at least one FMA on registers of that width, and no call into libm;
#                    zmm and ymm: rgba16f's conversions by F16C (vcvtph2ps, vcvtps2ph);
#   unfused          no FMA of any width, no F16C instruction (the SSE set runs on CPUs without
#                    it: rgba16f converts in software there), and no call into libm.
#   neon             AArch64, fused: vector FMAs (fmla on .4s), IEEE vector division (fdiv on .4s)
#                    and no reciprocal estimate (xsimd 8.1's neon64 division), the ARMv8 half
#                    conversions (fcvtl, fcvtn), the column fetch's table look-ups (tbl), no call
#                    into libm and none into xsimd (its generic fallbacks and wrappers).
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

# Every fused multiply-add form (vfmadd, vfmsub, vfnmadd, vfnmsub, vfmaddsub, vfmsubadd; any
# operand order and element type), one line each.
string(REGEX MATCHALL "[\t ]vf(n?m(add|sub)|maddsub|msubadd)[0-9]*[sp][sd][^\n]*" fmas "${listing}")
list(LENGTH fmas fma_count)
set(width_count 0)
foreach(line IN LISTS fmas)
  if(line MATCHES "%${EXPECT}")
    math(EXPR width_count "${width_count} + 1")
  endif()
endforeach()

# Calls into libm: a relocation against one of its functions (fmaf, floorf, lroundf, ...), which
# would mean a rounding step done out of line, and differently on each machine's libm.
set(libm "(fma|floor|ceil|trunc|round|lround|llround|nearbyint|rint|lrint|llrint|sqrt|fmin|fmax|exp|exp2|log|log2|pow|copysign|ldexp|frexp|modf)f?")
string(REGEX MATCHALL
  "R_X86_64_(PLT32|PC32|GOTPCREL|GOTPCRELX|REX_GOTPCRELX)[\t ]+${libm}(@[A-Za-z_.0-9]+)?[-+]"
  libm_calls "${listing}")
string(REGEX MATCHALL "R_AARCH64_(CALL26|JUMP26)[\t ]+${libm}[\n]" arm_libm_calls "${listing}")
list(APPEND libm_calls ${arm_libm_calls})
list(LENGTH libm_calls libm_count)

# F16C half-float conversions.
string(REGEX MATCHALL "[\t ]vcvt(ps2ph|ph2ps)[^\n]*" halves "${listing}")
list(LENGTH halves half_count)

string(REPLACE ";" ", " name "${names}")
if(libm_count GREATER 0)
  list(REMOVE_DUPLICATES libm_calls)
  string(REPLACE ";" "\n  " shown "${libm_calls}")
  message(FATAL_ERROR "${name}: ${libm_count} calls into libm (rounding done out of line):\n  ${shown}")
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
  # One line per instruction: "<address>:\t<mnemonic> <operands>" with --no-show-raw-insn.
  string(REGEX MATCHALL "\t(fmla|fmls)\tv[0-9]+\\.4s[^\n]*" neon_fmas "${listing}")
  string(REGEX MATCHALL "\tfdiv\tv[0-9]+\\.4s[^\n]*" neon_divisions "${listing}")
  string(REGEX MATCHALL "\t(frecpe|frecps|frsqrte|frsqrts)\t[^\n]*" estimates "${listing}")
  string(REGEX MATCHALL "\tfcvt[ln]2?\t[^\n]*" neon_halves "${listing}")
  string(REGEX MATCHALL "\ttbl\t[^\n]*" lookups "${listing}")
  string(REGEX MATCHALL "R_AARCH64_(CALL26|JUMP26)[\t ]+_ZN5xsimd[^\n]*" xsimd_calls "${listing}")
  foreach(list neon_fmas neon_divisions estimates neon_halves lookups xsimd_calls)
    list(LENGTH ${list} ${list}_count)
  endforeach()
  if(neon_fmas_count EQUAL 0)
    message(FATAL_ERROR "${name}: fused policy, but no fmla on .4s vectors: a vector multiply-add is computed with two roundings")
  endif()
  if(neon_divisions_count EQUAL 0 OR estimates_count GREATER 0)
    message(FATAL_ERROR "${name}: ${neon_divisions_count} vector fdiv and ${estimates_count} reciprocal estimates: "
                        "a vector division is not correctly rounded (xsimd 8.1's neon64 division; use vdiv)")
  endif()
  if(neon_halves_count EQUAL 0)
    message(FATAL_ERROR "${name}: no fcvtl/fcvtn: rgba16f is converting halves in software")
  endif()
  if(lookups_count EQUAL 0)
    message(FATAL_ERROR "${name}: no tbl: the column fetch gathers lane by lane instead of permuting")
  endif()
  if(xsimd_calls_count GREATER 0)
    list(GET xsimd_calls 0 first)
    message(FATAL_ERROR "${name}: ${xsimd_calls_count} calls into xsimd out of line (first: ${first})")
  endif()
  message(STATUS "${name}: ${neon_fmas_count} fmla, ${neon_divisions_count} fdiv and no reciprocal estimate, "
                 "${neon_halves_count} half conversions, ${lookups_count} table look-ups, no libm or xsimd call")
else()
  message(FATAL_ERROR "unknown EXPECT '${EXPECT}'")
endif()
