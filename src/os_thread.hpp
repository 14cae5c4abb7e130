// Internal: a thread of the library's pool, started through the operating system's own call, so
// that a thread that cannot be started is a false return (the pool then has fewer threads), never
// an exception: std::thread reports it by throwing, which a build without exceptions cannot
// catch. Its stack is the operating system's; no other memory is taken. (src/os_thread.cpp)
#pragma once

#if !defined(_WIN32)
#include <pthread.h>
#endif

namespace reproject {
namespace detail {

class OsThread {
 public:
  using Entry = void (*)(void* argument);

  // Runs entry(argument) on a new thread; false when none could be started.
  bool start(Entry entry, void* argument) noexcept;
  // Waits for the thread to return (a no-op if none was started).
  void join() noexcept;

 private:
  Entry entry_ = nullptr;
  void* argument_ = nullptr;
  bool started_ = false;
#if defined(_WIN32)
  void* handle_ = nullptr;  // a HANDLE (windows.h stays out of the headers)
#else
  pthread_t thread_{};
#endif
  friend struct OsThreadStart;
};

}  // namespace detail
}  // namespace reproject
