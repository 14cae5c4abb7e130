#!/usr/bin/env bash
# Builds the libraries reproject's tests, tools and benchmarks need, for 64-bit Windows with
# MinGW-w64, from Debian's own sources, into one prefix (README.md "Windows"; CI runs it too):
#
#   cmake/windows-dependencies.sh PREFIX
#
# then configure reproject with -DCMAKE_PREFIX_PATH=PREFIX and either toolchain file. Static
# libraries, built once with MinGW-w64's GCC (posix threads): clang --target=x86_64-w64-mingw32
# links the same libstdc++, so both builds share them.
#   GoogleTest        /usr/src/googletest (Debian's googletest package)
#   zlib              Debian's libz-mingw-w64-dev (already built for MinGW; linked statically)
#   libpng, Imath, OpenEXR, Google Benchmark
#                     Debian's source packages (libpng1.6, imath, openexr, benchmark) with Debian's
#                     patches, fetched with `apt-get source` through a private deb-src list of the
#                     suites this machine's apt already uses (nothing under /etc/apt changes)
#   xsimd             header-only: Debian's libxsimd-dev headers, copied with a minimal package
#                     config (Debian's names /usr/include, where the host's C headers would shadow
#                     MinGW's)
# Needs (Debian 12): cmake ninja-build g++-mingw-w64-x86-64-posix gcc-mingw-w64-x86-64-posix
# libz-mingw-w64-dev googletest libxsimd-dev dpkg-dev. About 4 minutes on 2 cores, most of it OpenEXR.
set -euo pipefail

if [ $# -ne 1 ]; then
  echo "usage: $0 PREFIX" >&2
  exit 2
fi
mkdir -p "$1"
prefix=$(cd "$1" && pwd)
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
toolchain=$here/toolchain-x86_64-w64-mingw32.cmake
jobs=${JOBS:-2}
work=$(mktemp -d -t reproject-windows-deps.XXXXXX)
trap 'rm -rf "$work"' EXIT
mingw=/usr/x86_64-w64-mingw32
zlib=(-DZLIB_LIBRARY=$mingw/lib/libz.a -DZLIB_INCLUDE_DIR=$mingw/include)

step() { printf '\n--- windows-dependencies: %s (%ds so far)\n' "$1" "$SECONDS"; }

# One CMake project: configure for Windows, build, install into the prefix.
build() {
  local name=$1 source=$2
  shift 2
  step "$name"
  cmake -S "$source" -B "$work/build-$name" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" -DCMAKE_PREFIX_PATH="$prefix" \
    -DBUILD_SHARED_LIBS=OFF "$@" > "$work/$name.log" 2>&1 || { tail -n 40 "$work/$name.log" >&2; return 1; }
  cmake --build "$work/build-$name" -j "$jobs" >> "$work/$name.log" 2>&1 || { tail -n 40 "$work/$name.log" >&2; return 1; }
  cmake --install "$work/build-$name" >> "$work/$name.log" 2>&1
}

step "Debian sources"
# deb-src lines for the suites apt already reads (its Packages index targets), in a private list.
apt_dir=$work/apt
mkdir -p "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" "$work/src"
apt_source_list() {
  apt-get indextargets --format '$(REPO_URI) $(RELEASE) $(COMPONENT)' 'Created-By: Packages' |
    sort -u | grep -v -e "${1:-^$}" | sed 's/^/deb-src /' > "$apt_dir/sources.list"
  apt=(-o Dir::Etc::SourceList="$apt_dir/sources.list" -o Dir::Etc::SourceParts=/nonexistent
       -o Dir::State::Lists="$apt_dir/lists" -o Dir::Cache="$apt_dir/cache" -o APT::Sandbox::User=root)
  apt-get "${apt[@]}" -q update > "$work/apt.log" 2>&1
}
packages=(libpng1.6 imath openexr benchmark)
apt_source_list
if ! (cd "$work/src" && apt-get "${apt[@]}" -q source "${packages[@]}" >> "$work/apt.log" 2>&1); then
  # A mirror that serves the release suites' sources but not the security suite's: take the
  # release's versions.
  echo "apt-get source failed with the security suite's sources; using the release suites' only:" >&2
  grep -E '^(E|W):' "$work/apt.log" >&2 || true
  rm -rf "$work/src" && mkdir -p "$work/src"
  apt_source_list "-security "
  (cd "$work/src" && apt-get "${apt[@]}" -q source "${packages[@]}" >> "$work/apt.log" 2>&1) ||
    { tail -n 20 "$work/apt.log" >&2; exit 1; }
fi
source_dir() { find "$work/src" -mindepth 1 -maxdepth 1 -type d -name "$1-*" | head -n 1; }
printf 'sources: %s\n' "$(cd "$work/src" && ls -d -- */ | tr -d / | tr '\n' ' ')"

step "xsimd (headers)"
mkdir -p "$prefix/include" "$prefix/lib/cmake/xsimd"
cp -a /usr/include/xsimd "$prefix/include/"
cat > "$prefix/lib/cmake/xsimd/xsimdConfig.cmake" <<'CONFIG'
# xsimd is header-only: Debian's libxsimd-dev headers, copied beside this file's prefix.
get_filename_component(_xsimd_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET xsimd)
  add_library(xsimd INTERFACE IMPORTED)
  set_target_properties(xsimd PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_xsimd_prefix}/include")
endif()
CONFIG
# Its version, from the headers (reproject's CMakeLists.txt checks it): a request for another major
# version is refused, as xsimd's own package does.
xsimd_version=$(sed -n 's/^#define XSIMD_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9][0-9]*\)$/\2/p' \
  "$prefix/include/xsimd/config/xsimd_config.hpp" | paste -sd .)
cat > "$prefix/lib/cmake/xsimd/xsimdConfigVersion.cmake" <<VERSION
set(PACKAGE_VERSION "$xsimd_version")
set(PACKAGE_VERSION_COMPATIBLE TRUE)
if(PACKAGE_FIND_VERSION AND (NOT PACKAGE_FIND_VERSION_MAJOR EQUAL "${xsimd_version%%.*}" OR PACKAGE_VERSION VERSION_LESS PACKAGE_FIND_VERSION))
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
endif()
VERSION

build googletest /usr/src/googletest -DBUILD_GMOCK=OFF
build libpng "$(source_dir libpng1.6)" -DPNG_SHARED=OFF -DPNG_EXECUTABLES=OFF -DPNG_TESTS=OFF "${zlib[@]}"
build imath "$(source_dir imath)" -DBUILD_TESTING=OFF
build openexr "$(source_dir openexr)" -DBUILD_TESTING=OFF -DOPENEXR_BUILD_TOOLS=OFF -DOPENEXR_INSTALL_TOOLS=OFF \
  -DOPENEXR_INSTALL_EXAMPLES=OFF -DOPENEXR_INSTALL_PKG_CONFIG=OFF "${zlib[@]}"
# Debian's rules give the version that upstream reads from git tags.
build benchmark "$(source_dir benchmark)" -DGIT_VERSION="$(basename "$(source_dir benchmark)" | sed 's/^benchmark-//')" \
  -DBENCHMARK_ENABLE_TESTING=OFF -DBENCHMARK_ENABLE_GTEST_TESTS=OFF -DBENCHMARK_ENABLE_WERROR=OFF \
  -DBENCHMARK_INSTALL_DOCS=OFF
step "done: $prefix"
