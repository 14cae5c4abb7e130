#include "counters.hpp"

#include <string>

namespace reproject::python {

void CallCounter::bind(py::module_& m, const char* calls) {
  const std::string what = calls;
  m.def(
      "_debug_max_concurrent_calls",
      [this] {
        std::lock_guard<std::mutex> lock(mutex_);
        return max_inside_;
      },
      ("Test only: the most " + what + " that were inside the library (GIL released) at once since the last reset.")
          .c_str());
  m.def(
      "_debug_reset_counters",
      [this](int rendezvous, double timeout_seconds) {
        std::lock_guard<std::mutex> lock(mutex_);
        max_inside_ = inside_;
        rendezvous_ = rendezvous;
        timeout_seconds_ = timeout_seconds;
      },
      py::arg("rendezvous") = 0, py::arg("timeout_seconds") = 0.0,
      ("Test only: resets the counter of " + what + "; with rendezvous = n, each call waits (GIL released, at most "
       "timeout_seconds) until n calls are inside.").c_str());
}

}  // namespace reproject::python
