#!/bin/sh
# Runs a Windows program under Wine (wine64) for the MinGW-w64 builds (CMAKE_CROSSCOMPILING_EMULATOR
# of toolchain-x86_64-w64-mingw32*.cmake):
#   wine-run.sh [--dll-dir DIR]... PROGRAM.exe [ARGUMENTS...]
# Each DIR (MinGW's runtime DLLs: libstdc++, libgcc_s, libwinpthread) goes on WINEPATH. Wine's own
# messages are off unless WINEDEBUG says otherwise. WINEPREFIX (default ~/.wine) is created on first
# use, once, under a lock, so that programs started in parallel do not each start creating it.
set -e
dll_path=""
while [ "$1" = "--dll-dir" ]; do
  dll_path="${dll_path:+$dll_path;}$2"
  shift 2
done
export WINEDEBUG="${WINEDEBUG--all}"
export WINEPATH="${dll_path}${WINEPATH:+;$WINEPATH}"
wine=$(command -v wine64 || true)
if [ -z "$wine" ] && [ -x /usr/lib/wine/wine64 ]; then wine=/usr/lib/wine/wine64; fi
if [ -z "$wine" ]; then
  echo "wine-run.sh: no wine64 (Debian: apt-get install wine64)" >&2
  exit 127
fi
prefix="${WINEPREFIX:-$HOME/.wine}"
if [ ! -f "$prefix/.wine-run-ready" ]; then
  mkdir -p "$(dirname "$prefix")"
  (
    flock 9
    if [ ! -f "$prefix/.wine-run-ready" ]; then
      WINEPREFIX="$prefix" "$wine" wineboot --init > /dev/null 2>&1
      touch "$prefix/.wine-run-ready"
    fi
  ) 9> "$prefix.lock"
fi
exec "$wine" "$@"
