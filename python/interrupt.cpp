#include "interrupt.hpp"

#include <pythread.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace reproject::python {

namespace {

namespace py = pybind11;

// How often the waiting main thread runs Python's signal handlers.
constexpr std::chrono::milliseconds kPollInterval{10};

// One helper thread that runs the main thread's calls, one at a time. It lives as long as the
// process (never joined or destroyed: at exit it is waiting, holding nothing), so that its
// thread-local row scratch is reused from call to call, as the calling thread's would be.
class Helper {
 public:
  Helper() : thread_([this] { serve(); }) { thread_.detach(); }

  // Starts `job`, unless a job is running (a signal handler that calls the module again).
  bool start(const std::function<void()>* job) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (job_ != nullptr || running_) return false;
    job_ = job;
    changed_.notify_all();
    return true;
  }
  // Waits at most `timeout` (forever when zero) for the job to end; true when it has.
  bool wait(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    auto finished = [this] { return job_ == nullptr && !running_; };
    if (timeout.count() == 0) {
      changed_.wait(lock, finished);
      return true;
    }
    return changed_.wait_for(lock, timeout, finished);
  }

 private:
  void serve() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      changed_.wait(lock, [this] { return job_ != nullptr; });
      const std::function<void()>* job = job_;
      running_ = true;
      lock.unlock();
      (*job)();
      lock.lock();
      job_ = nullptr;
      running_ = false;
      changed_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable changed_;
  const std::function<void()>* job_ = nullptr;
  bool running_ = false;
  std::thread thread_;
};

// The process's helper; a child made by fork() has no thread of its parent's, so it makes its own
// (the parent's object is left alone). Called with the GIL held, which serialises it.
Helper& helper() {
  static Helper* instance = nullptr;
  static pid_t owner = 0;
  if (instance == nullptr || owner != ::getpid()) {
    instance = new Helper();  // never deleted: see Helper
    owner = ::getpid();
  }
  return *instance;
}

// Whether this is the thread Python runs signal handlers on (the main thread; after a fork, the
// thread that forked). Called with the GIL held.
bool on_main_thread() {
  static unsigned long main_ident = 0;
  static pid_t owner = 0;
  if (owner != ::getpid()) {
    main_ident = py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
    owner = ::getpid();
  }
  return PyThread_get_thread_ident() == main_ident;
}

}  // namespace

Status run_interruptible(const std::function<Status()>& work, std::atomic<bool>& cancel) {
  Status status;
  const std::function<void()> job = [&] { status = work(); };
  if (!on_main_thread() || !helper().start(&job)) {
    py::gil_scoped_release release;
    return work();
  }
  Helper& running = helper();
  bool raised = false;
  PyThreadState* saved = PyEval_SaveThread();
  while (!running.wait(kPollInterval)) {
    PyEval_RestoreThread(saved);
    raised = PyErr_CheckSignals() != 0;  // runs the handlers; nonzero: one raised (the error is set)
    saved = PyEval_SaveThread();
    if (raised) {
      cancel.store(true, std::memory_order_relaxed);
      running.wait(std::chrono::milliseconds(0));
      break;
    }
  }
  PyEval_RestoreThread(saved);
  if (raised) throw py::error_already_set();
  return status;
}

}  // namespace reproject::python
