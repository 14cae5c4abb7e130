// Test-only counters of the Python module (python/): how many calls are inside the
// GIL-released region at once, and an optional rendezvous that holds each call there until `n`
// calls are inside (or a timeout passes), so that a test proves two Python threads run the library
// together without measuring time (tests/python/test_gil.py, test_metrics.py). warp's calls and
// the metrics' calls are counted apart.
#pragma once

#include <pybind11/pybind11.h>

#include <chrono>
#include <condition_variable>
#include <mutex>

#include "reproject/status.hpp"

namespace reproject::python {

namespace py = pybind11;

class CallCounter {
 public:
  // Runs `work` (the caller has released the GIL), counted.
  template <class Work>
  Status count(Work& work) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      ++inside_;
      if (inside_ > max_inside_) max_inside_ = inside_;
      changed_.notify_all();
      if (rendezvous_ > 0) {
        changed_.wait_for(lock, std::chrono::duration<double>(timeout_seconds_), [this] { return inside_ >= rendezvous_; });
      }
    }
    const Status status = work();
    std::lock_guard<std::mutex> lock(mutex_);
    --inside_;
    return status;
  }

  // Adds _debug_max_concurrent_calls() and _debug_reset_counters(rendezvous=0, timeout_seconds=0.0)
  // to `m`; `calls` names the calls counted in their docstrings ("warp calls").
  void bind(py::module_& m, const char* calls);

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  int inside_ = 0;
  int max_inside_ = 0;
  int rendezvous_ = 0;  // 0: off
  double timeout_seconds_ = 0.0;
};

}  // namespace reproject::python
