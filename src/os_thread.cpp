// src/os_thread.hpp: pthreads, or _beginthreadex on Windows (MSVC and MinGW alike).
#include "src/os_thread.hpp"

#if defined(_WIN32)
#define WIN32_LEAN_AND_MEAN
#define NOMINMAX
#include <process.h>
#include <windows.h>
#endif

namespace reproject {
namespace detail {

struct OsThreadStart {
#if defined(_WIN32)
  static unsigned __stdcall run(void* self) {
#else
  static void* run(void* self) {
#endif
    OsThread* thread = static_cast<OsThread*>(self);
    thread->entry_(thread->argument_);
#if defined(_WIN32)
    return 0;
#else
    return nullptr;
#endif
  }
};

bool OsThread::start(Entry entry, void* argument) noexcept {
  entry_ = entry;
  argument_ = argument;
#if defined(_WIN32)
  handle_ = reinterpret_cast<void*>(_beginthreadex(nullptr, 0, &OsThreadStart::run, this, 0, nullptr));
  started_ = handle_ != nullptr;
#else
  started_ = pthread_create(&thread_, nullptr, &OsThreadStart::run, this) == 0;
#endif
  return started_;
}

void OsThread::join() noexcept {
  if (!started_) return;
#if defined(_WIN32)
  WaitForSingleObject(static_cast<HANDLE>(handle_), INFINITE);
  CloseHandle(static_cast<HANDLE>(handle_));
  handle_ = nullptr;
#else
  pthread_join(thread_, nullptr);
#endif
  started_ = false;
}

}  // namespace detail
}  // namespace reproject
