// Run by ctest with REPROJECT_FORCE_ARCH set (see tests/CMakeLists.txt): the override must take
// effect when the CPU supports the named set, and be ignored (best supported set, with a line on
// stderr) when it does not or when the name is unknown.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "reproject/reproject.hpp"

int main() {
  const char* forced = std::getenv("REPROJECT_FORCE_ARCH");
  reproject::Arch wanted;
  if (forced == nullptr) {
    std::fprintf(stderr, "REPROJECT_FORCE_ARCH must be set\n");
    return 2;
  }
  const reproject::Arch got = reproject::selected_arch();
  if (!reproject::parse_arch(forced, &wanted)) {
    // An unknown name: the best supported set (ctest also requires the library's stderr line).
    // Within each processor family a later Arch is a wider, better set, and one processor runs
    // the sets of one family only (and scalar): the last supported value is the best.
    for (int a = reproject::kArchCount - 1; a >= 0; --a) {
      const reproject::Arch best = static_cast<reproject::Arch>(a);
      if (!reproject::arch_supported(best)) continue;
      if (got != best) return 1;
      std::printf("unknown name '%s': selected the best supported set, %s\n", forced, reproject::to_string(got));
      return 0;
    }
  }
  if (!reproject::arch_supported(wanted)) {
    std::printf("%s not supported here: selected %s\n", forced, reproject::to_string(got));
    return reproject::arch_supported(got) ? 0 : 1;
  }
  std::printf("REPROJECT_FORCE_ARCH=%s -> selected_arch() = %s\n", forced, reproject::to_string(got));
  return got == wanted ? 0 : 1;
}
