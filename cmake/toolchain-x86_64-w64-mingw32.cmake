# Cross compiling for 64-bit Windows (x86-64) with MinGW-w64's GCC, on a Debian or Ubuntu machine:
#
#   cmake -S . -B build-win -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-x86_64-w64-mingw32.cmake \
#     -DCMAKE_PREFIX_PATH=<the libraries built for Windows>
#
# (toolchain-x86_64-w64-mingw32-clang.cmake beside this file does the same with clang++;
# windows-dependencies.sh builds GoogleTest, libpng, OpenEXR and Google Benchmark for Windows from
# Debian's sources into such a prefix; README.md "Windows" has the whole recipe.) Nothing in it is
# specific to reproject. It expects Debian's g++-mingw-w64-x86-64-posix (the `posix` thread model:
# the default `win32` one has no std::thread or std::mutex) and wine64 to run what it builds.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)

set(_mingw_triple x86_64-w64-mingw32)

# The clang file sets its own compilers (and the GCC they borrow libstdc++ from) before including
# this one.
if(NOT _mingw_compilers_chosen)
  set(CMAKE_C_COMPILER ${_mingw_triple}-gcc-posix)
  set(CMAKE_CXX_COMPILER ${_mingw_triple}-g++-posix)
  set(_mingw_gcc ${_mingw_triple}-g++-posix)
endif()
set(CMAKE_RC_COMPILER ${_mingw_triple}-windres)

# Libraries, headers and packages for the target come only from MinGW-w64's own tree and from the
# prefixes given in CMAKE_PREFIX_PATH (each searched as a root of its own), never from the host's
# /usr: the host's headers and static libraries would be taken for Windows ones. Programs are the
# host's.
list(APPEND CMAKE_FIND_ROOT_PATH /usr/${_mingw_triple} ${CMAKE_PREFIX_PATH})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(ENV{PKG_CONFIG_LIBDIR} /usr/${_mingw_triple}/lib/pkgconfig)

find_program(CMAKE_OBJDUMP NAMES ${_mingw_triple}-objdump)

# Tests and any build step that runs a target program go through Wine (wine-run.sh: a quiet
# WINEDEBUG, a prefix created on first use, and the folders of MinGW's runtime DLLs, libstdc++,
# libgcc_s and libwinpthread, on WINEPATH).
execute_process(COMMAND ${_mingw_gcc} -print-file-name=libstdc++-6.dll
                OUTPUT_VARIABLE _mingw_libstdcxx OUTPUT_STRIP_TRAILING_WHITESPACE)
execute_process(COMMAND ${_mingw_gcc} -print-file-name=libwinpthread-1.dll
                OUTPUT_VARIABLE _mingw_winpthread OUTPUT_STRIP_TRAILING_WHITESPACE)
get_filename_component(_mingw_libstdcxx_dir "${_mingw_libstdcxx}" DIRECTORY)
get_filename_component(_mingw_winpthread_dir "${_mingw_winpthread}" DIRECTORY)
get_filename_component(_mingw_winpthread_dir "${_mingw_winpthread_dir}" REALPATH)
set(CMAKE_CROSSCOMPILING_EMULATOR ${CMAKE_CURRENT_LIST_DIR}/wine-run.sh
    --dll-dir ${_mingw_libstdcxx_dir} --dll-dir ${_mingw_winpthread_dir})
