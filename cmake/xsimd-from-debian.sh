#!/usr/bin/env bash
# Unpacks the xsimd (and xtl, which Debian's xsimd CMake package requires) of another Debian
# suite into a prefix of its own, with apt itself and without touching the machine's apt
# configuration: a private sources list, lists and cache. xsimd is header-only, so the amd64
# package serves an aarch64 cross build too.
#   cmake/xsimd-from-debian.sh trixie /tmp/xsimd-trixie   # xsimd 13.2.0
#   cmake/xsimd-from-debian.sh sid /tmp/xsimd-sid         # xsimd 14.3.0 (on 2026-11-27)
# then configure with -DCMAKE_PREFIX_PATH=PREFIX/usr. Prints the unpacked xsimd version.
set -euo pipefail
suite=${1:?usage: $0 SUITE PREFIX}
prefix=${2:?usage: $0 SUITE PREFIX}
# The mirror the machine already uses (deb822 or one-line sources), else Debian's own.
mirror=$(sed -n 's/^URIs:[[:space:]]*\(http[^[:space:]]*\/debian\)\/*$/\1/p' /etc/apt/sources.list.d/*.sources 2>/dev/null | head -n 1)
if [ -z "$mirror" ]; then
  mirror=$(sed -n 's/^deb[[:space:]]\+\(\[[^]]*\][[:space:]]\+\)\?\(http[^[:space:]]*\/debian\)\/*[[:space:]].*/\2/p' /etc/apt/sources.list 2>/dev/null | head -n 1)
fi
mirror=${mirror:-http://deb.debian.org/debian}
state=$(mktemp -d)
trap 'rm -rf "$state"' EXIT
mkdir -p "$state/lists/partial" "$state/cache/archives/partial" "$prefix"
echo "deb [arch=amd64 signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $mirror $suite main" > "$state/sources.list"
opts=(-o "Dir::Etc::SourceList=$state/sources.list" -o Dir::Etc::SourceParts=/nonexistent
      -o "Dir::State::Lists=$state/lists" -o "Dir::Cache=$state/cache" -o Debug::NoLocking=1)
for attempt in 1 2 3; do
  if apt-get "${opts[@]}" update > "$state/update.log" 2>&1; then break; fi
  if [ "$attempt" = 3 ]; then cat "$state/update.log" >&2; exit 1; fi
  sleep 10
done
(cd "$state" && apt-get "${opts[@]}" download "libxsimd-dev/$suite" "xtl-dev/$suite" > download.log 2>&1) ||
  { cat "$state/download.log" >&2; exit 1; }
for deb in "$state"/*.deb; do dpkg -x "$deb" "$prefix"; done
sed -n 's/^set(PACKAGE_VERSION "\(.*\)")/xsimd \1/p' "$prefix/usr/share/cmake/xsimd/xsimdConfigVersion.cmake"
