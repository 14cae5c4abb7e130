# ctest ObjectCode.<name>: reads one kernel object's machine code, so that a defect of an
# instruction set this CPU cannot run still fails here (the AVX-512 table once lost its FMAs to a
# generic xsimd fallback and nobody's machine could run it).
#   cmake -DOBJDUMP=<objdump> -DOBJECTS=<a.o|b.o|...> -DPOLICY=<policy> -P check_object_code.cmake
# EXPECT (over the objects together):
#   zmm | ymm | xmm  fused: at least one FMA on registers of that width, and no call into libm;
#                    zmm and ymm: rgba16f's conversions by F16C (vcvtph2ps, vcvtps2ph);
#   unfused          no FMA of any width, no F16C instruction (the SSE set runs on CPUs without
#                    it: rgba16f converts in software there), and no call into libm.
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

# Calls into libm: a relocation against one of its functions (fmaf, floorf, ...), which would mean
# a rounding step done out of line, and differently on each machine's libm.
string(REGEX MATCHALL
  "R_X86_64_(PLT32|PC32|GOTPCREL|GOTPCRELX|REX_GOTPCRELX)[\t ]+(fma|floor|ceil|trunc|round|nearbyint|rint|lrint|llrint|sqrt|fmin|fmax|exp|exp2|log|log2|pow|copysign|ldexp|frexp|modf)f?(@[A-Za-z_.0-9]+)?[-+]"
  libm_calls "${listing}")
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
else()
  message(FATAL_ERROR "unknown EXPECT '${EXPECT}'")
endif()
