// What a run that covers "every instruction set" really executed on this CPU, as one line for the
// log, e.g. "bit-identity: scalar sse avx2 executed; avx512 compiled but not supported by this CPU",
// so that a green run on a machine without AVX-512 cannot be read as covering AVX-512.
#pragma once

#include <string>

#include "reproject/reproject.hpp"

namespace reproject {

inline std::string arch_report(const char* what) {
  std::string executed, not_runnable;
  for (int a = 0; a < kArchCount; ++a) {
    const Arch arch = static_cast<Arch>(a);
    std::string& list = arch_supported(arch) ? executed : not_runnable;
    list += std::string(list.empty() ? "" : " ") + to_string(arch);
  }
  std::string line = std::string(what) + ": " + executed + " executed";
  line += not_runnable.empty() ? "; every compiled set ran" : "; " + not_runnable + " compiled but not supported by this CPU";
  return line;
}

}  // namespace reproject
