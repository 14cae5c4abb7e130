// Ctrl-C during a long call (python/warp.cpp). Python runs its signal handlers (the one
// that raises KeyboardInterrupt among them) only on the main thread and only between bytecodes,
// so a call that runs the kernels on the main thread answers Ctrl-C when it returns, seconds
// later for a large frame. run_interruptible runs such a call on a helper thread instead, with
// the GIL released, while the main thread waits and, every 10 ms, takes the GIL to run the
// handlers: one that raises sets the call's cancel flag (Options::cancel), the call stops within
// a block of rows, and the exception propagates.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <functional>

#include "reproject/status.hpp"

namespace reproject::python {

// Runs `work` (which reads `cancel`) with the GIL released and returns its status. On the main
// thread, a signal handler that raises during the call (KeyboardInterrupt) sets `cancel`, waits
// for `work` to return, and raises its exception (py::error_already_set). On other threads, which
// Python's signals never reach, `work` runs on the calling thread.
Status run_interruptible(const std::function<Status()>& work, std::atomic<bool>& cancel);

}  // namespace reproject::python
