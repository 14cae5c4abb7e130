# Cross compiling for 64-bit Windows (x86-64) with clang, on a Debian or Ubuntu machine:
#
#   cmake -S . -B build-win-clang -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-x86_64-w64-mingw32-clang.cmake \
#     -DCMAKE_PREFIX_PATH=<the libraries built for Windows>
#
# clang targets MinGW-w64 by itself (--target=x86_64-w64-mingw32: LLVM's code generation, as
# clang-cl uses, and lld for the link) with MinGW-w64's headers, C runtime and libstdc++, so its
# objects link with those GCC built (the dependencies are shared). Debian's clang 14 finds MinGW's
# C headers but not the libstdc++ of g++-mingw-w64-x86-64-posix, whose folder is named `12-posix`
# rather than a version (clang reads the folder names as versions): its three include/c++ folders
# and its library folder are named here. MinGW-w64's tree is the sysroot, so that nothing of the
# host's /usr/include (which clang searches otherwise) is taken for a Windows header.
set(CMAKE_C_COMPILER clang)
set(CMAKE_CXX_COMPILER clang++)
set(CMAKE_C_COMPILER_TARGET x86_64-w64-mingw32)
set(CMAKE_CXX_COMPILER_TARGET x86_64-w64-mingw32)
set(CMAKE_SYSROOT /usr/x86_64-w64-mingw32)
set(_mingw_gcc x86_64-w64-mingw32-g++-posix)
set(_mingw_compilers_chosen TRUE)

execute_process(COMMAND ${_mingw_gcc} -print-libgcc-file-name
                OUTPUT_VARIABLE _mingw_libgcc OUTPUT_STRIP_TRAILING_WHITESPACE)
get_filename_component(_mingw_gcc_dir "${_mingw_libgcc}" DIRECTORY)
set(_mingw_cxx_include ${_mingw_gcc_dir}/include/c++)
# Standard include directories come after the project's own whatever CMAKE_CXX_FLAGS says (a
# -DCMAKE_CXX_FLAGS=-Werror would replace flags set through CMAKE_CXX_FLAGS_INIT).
set(CMAKE_CXX_STANDARD_INCLUDE_DIRECTORIES ${_mingw_cxx_include} ${_mingw_cxx_include}/x86_64-w64-mingw32
    ${_mingw_cxx_include}/backward)
# libgcc and libstdc++ (C programs link libgcc too). A CMAKE_*_LINKER_FLAGS given on the command
# line replaces these: keep them in it.
foreach(_kind EXE SHARED MODULE)
  set(CMAKE_${_kind}_LINKER_FLAGS_INIT "-fuse-ld=lld -L${_mingw_gcc_dir}")
endforeach()
include(${CMAKE_CURRENT_LIST_DIR}/toolchain-x86_64-w64-mingw32.cmake)
