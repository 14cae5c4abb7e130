# ctest Library.NoGlobalConstructors: no object of the library archive runs code at load time
# (no .init_array or .ctors section): the library starts nothing (threads, allocations, CPU
# detection) before the host's first call, so an engine can set its allocator first.
# Sections with a priority of 100 or less (.init_array.00099, .init_array.1, ...) are the
# toolchain's own: sanitizers, coverage and profiling register their modules there, in every
# object, and C++ reserves those priorities for the implementation (a program's own start at 101).
# They are reported, not failed, so an instrumented build passes on what the library itself does.
#   cmake -DOBJDUMP=<objdump> -DARCHIVE=<libreproject.a> -P check_no_constructors.cmake
execute_process(COMMAND "${OBJDUMP}" -h "${ARCHIVE}" OUTPUT_VARIABLE listing ERROR_VARIABLE errors RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${OBJDUMP} -h ${ARCHIVE} failed (${result}): ${errors}")
endif()
set(member "")
set(found "")
set(instrumented "")
string(REPLACE "\n" ";" lines "${listing}")
foreach(line IN LISTS lines)
  if(line MATCHES "^([^ \t]+\\.o(bj)?):[ \t]+file format")
    set(member "${CMAKE_MATCH_1}")
  elseif(line MATCHES "[ \t](\\.init_array|\\.ctors)(\\.([0-9]+))?[ \t]")
    set(section "${CMAKE_MATCH_1}${CMAKE_MATCH_2}")
    set(priority "${CMAKE_MATCH_3}")
    if(priority STREQUAL "" OR priority GREATER 100)
      list(APPEND found "${member} (${section})")
    else()
      list(APPEND instrumented "${section}")
    endif()
  endif()
endforeach()
if(found)
  list(REMOVE_DUPLICATES found)
  string(REPLACE ";" "\n  " shown "${found}")
  message(FATAL_ERROR "objects with global constructors:\n  ${shown}")
endif()
string(REGEX MATCHALL "file format" members "${listing}")
list(LENGTH members count)
if(instrumented)
  list(REMOVE_DUPLICATES instrumented)
  string(REPLACE ";" ", " shown "${instrumented}")
  message(STATUS "the toolchain's own constructors (instrumentation) left aside: ${shown}")
endif()
message(STATUS "${count} objects, none with a global constructor")
