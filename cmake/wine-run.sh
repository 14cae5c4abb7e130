#!/bin/sh
# Runs a Windows program under Wine (wine64) for the MinGW-w64 builds (CMAKE_CROSSCOMPILING_EMULATOR
# of toolchain-x86_64-w64-mingw32*.cmake):
#   wine-run.sh [--dll-dir DIR]... PROGRAM.exe [ARGUMENTS...]
# Each DIR (MinGW's runtime DLLs: libstdc++, libgcc_s, libwinpthread) goes on WINEPATH. Wine's own
# messages are off unless WINEDEBUG says otherwise. WINEPREFIX (default ~/.wine) is created on first
# use, once, under a lock, so that programs started in parallel do not each start creating it.
# Wine's server is kept for 30 s after its last program ends (its default is 3 s): a program
# started while the server is shutting down can fail to reach it ("wine client error: recvmsg:
# Connection reset by peer"), which a test run, one program after another, would otherwise meet.
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
server=$(command -v wineserver64 || command -v wineserver || echo /usr/lib/wine/wineserver64)
prefix="${WINEPREFIX:-$HOME/.wine}"
mkdir -p "$prefix"
export WINEPREFIX="$prefix"
(
  flock 9 || exit
  # A server of our own when none runs (wineserver exits at once, status 2, if one does). Wine's
  # services (services.exe, winedevice.exe, ...) then start here, with their output going
  # nowhere: started by the program below, they would hold its output open for as long as the
  # server lives, and a test runner waits for that.
  # (Neither may inherit the lock's descriptor: it would stay locked as long as they live.)
  if "$server" -p30 > /dev/null 2>&1 < /dev/null 9>&- || [ ! -f "$prefix/.wine-run-ready" ]; then
    "$wine" wineboot --init > /dev/null 2>&1 < /dev/null 9>&- || exit
    touch "$prefix/.wine-run-ready"
  fi
) 9> "$prefix.lock" || {
  # Said, not silent: a test that fails here has printed nothing of its own.
  status=$?
  echo "wine-run.sh: Wine could not be started in $prefix (status $status)" >&2
  exit "$status"
}
exec "$wine" "$@"
