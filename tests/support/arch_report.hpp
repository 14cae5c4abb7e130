// The instruction sets as the library names them (Arch, kArchCount, to_string), for the tests'
// "every arch" lists, so that a set the library gains is tested everywhere without editing them;
// and what a run that covers "every instruction set" really executed on this machine, as one
// line for the log, e.g. "bit-identity: scalar sse avx2 executed; avx512 not run here (...)",
// so that a green run on a machine without AVX-512 cannot be read as covering AVX-512.
#pragma once

#include <string>
#include <vector>

#include "reproject/reproject.hpp"

namespace reproject {

// Every Arch value, in the enum's order.
inline std::vector<Arch> every_arch() {
  std::vector<Arch> arches;
  for (int a = 0; a < kArchCount; ++a) arches.push_back(static_cast<Arch>(a));
  return arches;
}

// Every set but scalar, the ones that may be missing here.
inline std::vector<Arch> every_simd_arch() {
  std::vector<Arch> arches;
  for (Arch arch : every_arch()) {
    if (arch != Arch::scalar) arches.push_back(arch);
  }
  return arches;
}

// "scalar, sse, avx2, avx512": the names parse_arch accepts, as the library's messages list them.
inline std::string arch_names(const char* separator = ", ") {
  std::string names;
  for (Arch arch : every_arch()) names += std::string(names.empty() ? "" : separator) + to_string(arch);
  return names;
}

// Why a test of `arch` did not run. arch_supported() is false both for a set this CPU lacks and
// for one built only for another processor family (the x86 sets on AArch64), and cannot tell the two apart.
inline std::string not_run_reason(Arch arch) {
  return std::string(to_string(arch)) + " not run: not compiled in for this processor, or not supported by this CPU";
}

inline std::string arch_report(const char* what) {
  std::string executed, not_runnable;
  for (Arch arch : every_arch()) {
    std::string& list = arch_supported(arch) ? executed : not_runnable;
    list += std::string(list.empty() ? "" : " ") + to_string(arch);
  }
  std::string line = std::string(what) + ": " + executed + " executed";
  line += not_runnable.empty() ? "; every set ran"
                               : "; " + not_runnable + " not run here (not compiled in for this processor, or not supported by this CPU)";
  return line;
}

}  // namespace reproject
