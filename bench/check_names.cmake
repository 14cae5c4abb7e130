# ctest BenchmarkNames: every name reproject_bench registers has the form the benchmark issue fixes,
# with no suffix of Google Benchmark's own (such as "/real_time"), and the required ones exist.
#   cmake -DBENCH=<path to reproject_bench> -DARCHES=<scalar|sse|...> [-DEMULATOR=<qemu-aarch64|...>]
#         -P check_names.cmake
# (ARCHES: the instruction sets the library names, cmake/arches.cmake; EMULATOR: the words that
# run a cross build's program, separated by |, empty for a native build.)
cmake_policy(SET CMP0007 NEW)
if(NOT ARCHES)
  message(FATAL_ERROR "check_names.cmake needs -DARCHES=<scalar|sse|...>")
endif()
string(REPLACE "|" ";" emulator "${EMULATOR}")
execute_process(COMMAND ${emulator} "${BENCH}" --benchmark_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "reproject_bench --benchmark_list_tests failed: ${result}")
endif()
string(REPLACE "\n" ";" names "${listing}")
list(FILTER names EXCLUDE REGEX "^$")
list(LENGTH names count)
set(method "(pair_)?(scanline|march16|single|secant|exact)/(${ARCHES})")
# Engine-native frames: /<colour>+<depth> (rgba32f+float is the float baseline), and the band of a
# frame's rows that stays in cache: /<colour>+<depth>/band:32.
set(format "(rgba32f\\+float|rgba8\\+unorm24_s8|rgba8_srgb\\+float|rgba8_srgb\\+unorm24_s8|rgba16f\\+float|rgba8\\+unorm16)(/band:32)?")
foreach(name IN LISTS names)
  if(NOT name MATCHES "^${method}/[0-9]+x[0-9]+/threads:[12](/sep:(8|32|128)|/rgba|/grey|/near:fixed|/two_calls|/${format})?$"
     AND NOT name MATCHES "^roofline/[0-9]+x[0-9]+/threads:[12](/rgba|/grey|/${format})?$")
    message(FATAL_ERROR "benchmark name out of form: '${name}'")
  endif()
endforeach()
# Scalar always runs, so its names are always registered.
foreach(required
    roofline/1280x720/threads:1 roofline/1920x1080/threads:2 roofline/3840x2160/threads:2
    roofline/512x512/threads:1/grey march16/scalar/512x512/threads:1/grey
    march16/scalar/1920x1080/threads:2 scanline/scalar/1920x1080/threads:1/sep:128
    exact/scalar/3840x2160/threads:1 single/scalar/1920x1080/threads:2/rgba
    pair_secant/scalar/1920x1080/threads:2 exact/scalar/1920x1080/threads:1/near:fixed
    roofline/1920x1080/threads:1/rgba32f+float roofline/1920x1080/threads:2/rgba8+unorm24_s8
    roofline/1920x1080/threads:2/rgba8_srgb+float roofline/1920x1080/threads:2/rgba8_srgb+unorm24_s8
    roofline/1920x1080/threads:2/rgba16f+float
    roofline/1920x1080/threads:2/rgba8+unorm16 roofline/3840x2160/threads:1/rgba8+unorm24_s8
    roofline/3840x2160/threads:2/rgba32f+float roofline/1920x1080/threads:2/rgba8+unorm24_s8/band:32
    roofline/1920x1080/threads:1/rgba32f+float/band:32)
  list(FIND names "${required}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "benchmark missing: ${required}")
  endif()
endforeach()
message(STATUS "${count} benchmark names, all of the fixed form")
