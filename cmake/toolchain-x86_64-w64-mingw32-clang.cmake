# Cross compiling for 64-bit Windows (x86-64) with clang, on a Debian or Ubuntu machine:
#
#   cmake -S . -B build-win-clang -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-x86_64-w64-mingw32-clang.cmake \
#     -DCMAKE_PREFIX_PATH=<the libraries built for Windows>
#
# clang targets MinGW-w64 by itself (--target=x86_64-w64-mingw32: LLVM's code generation, as
# clang-cl uses, and lld for the link) with MinGW-w64's headers, C runtime and libstdc++, so its
# objects link with those GCC built (the dependencies are shared). Debian's clang 14 finds MinGW's
# C headers but not the libstdc++ of g++-mingw-w64-x86-64-posix, whose folder is named `12-posix`
# rather than a version: its three include/c++ folders and its library folder are named here.
set(CMAKE_C_COMPILER clang)
set(CMAKE_CXX_COMPILER clang++)
set(CMAKE_C_COMPILER_TARGET x86_64-w64-mingw32)
set(CMAKE_CXX_COMPILER_TARGET x86_64-w64-mingw32)
set(_mingw_gcc x86_64-w64-mingw32-g++-posix)
set(_mingw_compilers_chosen TRUE)

execute_process(COMMAND ${_mingw_gcc} -print-libgcc-file-name
                OUTPUT_VARIABLE _mingw_libgcc OUTPUT_STRIP_TRAILING_WHITESPACE)
get_filename_component(_mingw_gcc_dir "${_mingw_libgcc}" DIRECTORY)
set(_mingw_cxx_include ${_mingw_gcc_dir}/include/c++)
string(JOIN " " _mingw_cxx_flags -isystem ${_mingw_cxx_include} -isystem ${_mingw_cxx_include}/x86_64-w64-mingw32
       -isystem ${_mingw_cxx_include}/backward)
set(CMAKE_CXX_FLAGS_INIT "${_mingw_cxx_flags}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-fuse-ld=lld -L${_mingw_gcc_dir}")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-fuse-ld=lld -L${_mingw_gcc_dir}")
set(CMAKE_MODULE_LINKER_FLAGS_INIT "-fuse-ld=lld -L${_mingw_gcc_dir}")
include(${CMAKE_CURRENT_LIST_DIR}/toolchain-x86_64-w64-mingw32.cmake)
