# The instruction sets the library names, in its order, read from the public header's
# `enum class Arch` (include/reproject/reproject.hpp): REPROJECT_ARCHES (a list) and
# REPROJECT_ARCH_LIST ("scalar, sse, avx2, avx512"), for the tests and checks that go through every
# set, so that a set the library gains is picked up without editing them.
file(STRINGS ${PROJECT_SOURCE_DIR}/include/reproject/reproject.hpp _reproject_arch_enum REGEX "^enum class Arch ")
string(REGEX MATCH "{([a-z0-9_, ]+)}" _reproject_arch_enum "${_reproject_arch_enum}")
string(REPLACE " " "" REPROJECT_ARCHES "${CMAKE_MATCH_1}")
string(REPLACE "," ";" REPROJECT_ARCHES "${REPROJECT_ARCHES}")
if(NOT REPROJECT_ARCHES)
  message(FATAL_ERROR "include/reproject/reproject.hpp: no `enum class Arch : ... { ... };` line to read the instruction sets from")
endif()
string(REPLACE ";" ", " REPROJECT_ARCH_LIST "${REPROJECT_ARCHES}")
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/include/reproject/reproject.hpp)
