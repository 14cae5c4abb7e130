# Cross compiling for 64-bit ARM Linux (aarch64) on a Debian or Ubuntu x86-64 machine, with GCC:
#
#   cmake -S . -B build-arm -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-aarch64-linux-gnu.cmake
#
# (toolchain-aarch64-linux-gnu-clang.cmake beside this file does the same with clang++.)
# Nothing in it is specific to reproject. It expects Debian's cross compiler and multiarch
# packages (README.md lists them): the compilers aarch64-linux-gnu-gcc/g++, the target's
# libraries under /usr/lib/aarch64-linux-gnu (after `dpkg --add-architecture arm64`, e.g.
# libgtest-dev:arm64, libpng-dev:arm64, libxsimd-dev:arm64), and qemu-user to run what it builds.
# A package installed into a private prefix instead (one whose -dev package cannot be installed
# beside the host's, such as OpenEXR's) is found with -DCMAKE_PREFIX_PATH=<prefix>/usr.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(_aarch64_triple aarch64-linux-gnu)

# The clang file sets its own compilers before including this one.
if(NOT _aarch64_compilers_chosen)
  set(CMAKE_C_COMPILER ${_aarch64_triple}-gcc)
  set(CMAKE_CXX_COMPILER ${_aarch64_triple}-g++)
endif()

# Debian multiarch: the target's libraries, CMake packages and pkg-config files live under
# /usr/lib/aarch64-linux-gnu (xsimd's xsimdConfig.cmake too, although the library is header-only),
# beside the host's under /usr/lib/x86_64-linux-gnu. Naming the architecture makes find_package
# and find_library look in the target's folder and never in the host's. The cross C library of
# libc6-dev-arm64-cross is under /usr/aarch64-linux-gnu.
set(CMAKE_LIBRARY_ARCHITECTURE ${_aarch64_triple})
set(CMAKE_FIND_ROOT_PATH /usr/${_aarch64_triple})
# Programs (objdump, python3 for build scripts, ...) are the host's; libraries, headers and
# packages are searched in the root path first, then in the host's folders, where the
# architecture's folder above keeps the host's own libraries out.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
# pkg-config (used by some Find modules) reads the target's .pc files only.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/${_aarch64_triple}/pkgconfig:/usr/share/pkgconfig)

# The target's binutils (objdump reads the object code of the tests' ObjectCode checks).
find_program(CMAKE_OBJDUMP NAMES ${_aarch64_triple}-objdump)

# Tests, test discovery and any build step that runs a target program go through user-mode
# emulation. When the target's own C library is installed (libc6:arm64, which the arm64 -dev
# packages pull in) its loader is at /lib/ld-linux-aarch64.so.1 and qemu needs no prefix; with
# `-L /usr/aarch64-linux-gnu` it would pair the cross package's ld.so with the multiarch libc.so.6,
# two different builds of glibc. Without libc6:arm64, the cross C library is the only one there is.
if(EXISTS /lib/ld-linux-aarch64.so.1)
  set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64)
else()
  set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/${_aarch64_triple})
endif()
