# Cross compiling for 64-bit ARM Linux (aarch64) with clang, on a Debian or Ubuntu x86-64 machine:
#
#   cmake -S . -B build-arm-clang -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-aarch64-linux-gnu-clang.cmake
#
# clang is a cross compiler by itself (--target=aarch64-linux-gnu); it takes the C and C++
# libraries, the start files and the linker (aarch64-linux-gnu-ld) from the same Debian packages as
# the GCC toolchain (g++-aarch64-linux-gnu, binutils-aarch64-linux-gnu), so everything else is
# shared with toolchain-aarch64-linux-gnu.cmake.
set(CMAKE_C_COMPILER clang)
set(CMAKE_CXX_COMPILER clang++)
set(CMAKE_C_COMPILER_TARGET aarch64-linux-gnu)
set(CMAKE_CXX_COMPILER_TARGET aarch64-linux-gnu)
set(_aarch64_compilers_chosen TRUE)
include(${CMAKE_CURRENT_LIST_DIR}/toolchain-aarch64-linux-gnu.cmake)
