// Internal: what the entry points need of the library's memory (kernels/memory.hpp allocates;
// include/reproject/memory.hpp is the host's side): a call's scope, which set_allocator waits out,
// and the status a call returns when the allocator had nothing.
#pragma once

#include "kernels/memory.hpp"
#include "reproject/status.hpp"

namespace reproject {
namespace detail {

// Marks a call that may allocate as running, for its lifetime (set_allocator is refused
// meanwhile). Cheap: one atomic increment and decrement.
class CallScope {
 public:
  CallScope() noexcept;
  ~CallScope();
  CallScope(const CallScope&) = delete;
  CallScope& operator=(const CallScope&) = delete;
};

// StatusCode::out_of_memory naming what could not be had, e.g. "reproject: out of memory (row
// scratch)". The message is built without allocating.
Status out_of_memory(const char* function, const char* what) noexcept;

}  // namespace detail
}  // namespace reproject
