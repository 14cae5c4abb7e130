// Run by ctest with REPROJECT_FORCE_ARCH set (see tests/CMakeLists.txt): the override must take
// effect when the CPU supports the named set, and be ignored (best supported set) otherwise.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "reproject/reproject.hpp"

int main() {
  const char* forced = std::getenv("REPROJECT_FORCE_ARCH");
  reproject::Arch wanted;
  if (forced == nullptr || !reproject::parse_arch(forced, &wanted)) {
    std::fprintf(stderr, "REPROJECT_FORCE_ARCH must name an arch\n");
    return 2;
  }
  const reproject::Arch got = reproject::selected_arch();
  if (!reproject::arch_supported(wanted)) {
    std::printf("%s not supported here: selected %s\n", forced, reproject::to_string(got));
    return reproject::arch_supported(got) ? 0 : 1;
  }
  std::printf("REPROJECT_FORCE_ARCH=%s -> selected_arch() = %s\n", forced, reproject::to_string(got));
  return got == wanted ? 0 : 1;
}
