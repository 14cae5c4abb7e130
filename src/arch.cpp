// Which instruction set runs: the best one this build compiled and the CPU *and* the operating
// system support (kernels/cpu.hpp), chosen once, unless REPROJECT_FORCE_ARCH names another
// supported one.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "kernels/cpu.hpp"
#include "kernels/dispatch.hpp"
#include "reproject/reproject.hpp"

namespace reproject {
namespace {

Arch best_supported() {
  // Best first; a processor family compiles the sets of its own only.
  for (Arch arch : {Arch::avx512, Arch::avx2, Arch::sse, Arch::neon}) {
    if (arch_supported(arch)) return arch;
  }
  return Arch::scalar;
}

// Runs once per process. A forced set that is unknown or that this CPU cannot run is said on
// stderr (once), so that nobody reads a run as covering a set it did not execute.
Arch choose() {
  const Arch best = best_supported();
  const char* forced = std::getenv("REPROJECT_FORCE_ARCH");
  if (forced != nullptr && *forced != '\0') {  // set and not empty (empty: as if unset)
    Arch arch;
    if (!parse_arch(forced, &arch)) {
      char names[64] = "";
      for (int i = 0; i < kArchCount; ++i) {
        std::strncat(names, i ? ", " : "", sizeof names - std::strlen(names) - 1);
        std::strncat(names, to_string(static_cast<Arch>(i)), sizeof names - std::strlen(names) - 1);
      }
      std::fprintf(stderr, "reproject: REPROJECT_FORCE_ARCH='%s' is not one of %s; using %s\n", forced, names,
                   to_string(best));
    } else if (!arch_supported(arch)) {
      std::fprintf(stderr, "reproject: REPROJECT_FORCE_ARCH=%s is not supported by this CPU; using %s\n", forced,
                   to_string(best));
    } else {
      return arch;
    }
  }
  return best;
}

}  // namespace

bool arch_supported(Arch arch) noexcept {
  // The CPU first: compiled_kernels() runs code of the set's own translation unit (its table's
  // initialiser), which the compiler may build with that set's instructions (SIGILL otherwise).
  return detail::cpu_supports(arch) && detail::compiled_kernels(arch) != nullptr;
}

Arch selected_arch() noexcept {
  static const Arch arch = choose();
  return arch;
}

}  // namespace reproject
