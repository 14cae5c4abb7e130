// The library's memory (include/reproject/memory.hpp, kernels/memory.hpp): one allocator for every
// byte, the host's or the default, and the count of what is out, so that the allocator can change
// only when nothing is out and release_memory() can show it gave everything back.
#include "reproject/memory.hpp"

#include <atomic>
#include <cstdint>
#include <mutex>
#include <new>

#include "src/bands.hpp"
#include "src/memory.hpp"
#include "src/thread_pool.hpp"

namespace reproject {
namespace detail {
namespace {

struct State {
  std::mutex mutex;  // guards everything below, and every call into the allocator
  Allocator allocator{};
  std::size_t bytes = 0;
  std::atomic<int> calls{0};
};

// Constructed on first use (no constructor runs at load time).
State& state() noexcept {
  static State s;
  return s;
}

void* default_allocate(std::size_t size, std::size_t alignment) noexcept {
  return ::operator new(size, std::align_val_t(alignment), std::nothrow);
}
void default_deallocate(void* pointer, std::size_t alignment) noexcept {
  ::operator delete(pointer, std::align_val_t(alignment), std::nothrow);
}

}  // namespace

void* allocate(std::size_t size, std::size_t alignment) noexcept {
  if (size == 0) size = 1;
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  const Allocator& a = s.allocator;
  void* pointer = a.allocate != nullptr ? a.allocate(a.user, size, alignment) : default_allocate(size, alignment);
  if (pointer == nullptr) return nullptr;
  if (reinterpret_cast<std::uintptr_t>(pointer) % alignment != 0) {
    // A host allocator that ignores the alignment: refuse its block rather than misread it.
    if (a.deallocate != nullptr) a.deallocate(a.user, pointer, size, alignment);
    return nullptr;
  }
  s.bytes += size;
  return pointer;
}

void deallocate(void* pointer, std::size_t size, std::size_t alignment) noexcept {
  if (pointer == nullptr) return;
  if (size == 0) size = 1;
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  const Allocator& a = s.allocator;
  if (a.deallocate != nullptr) a.deallocate(a.user, pointer, size, alignment);
  else default_deallocate(pointer, alignment);
  s.bytes -= size;
}

CallScope::CallScope() noexcept { state().calls.fetch_add(1, std::memory_order_acq_rel); }
CallScope::~CallScope() { state().calls.fetch_sub(1, std::memory_order_acq_rel); }

Status out_of_memory(const char* function, const char* what) noexcept {
  return Status(StatusCode::out_of_memory, "%s: out of memory (%s): the allocator returned null", function, what);
}

}  // namespace detail

Status set_allocator(const Allocator* allocator) noexcept {
  if (allocator != nullptr && ((allocator->allocate == nullptr) != (allocator->deallocate == nullptr)))
    return Status(StatusCode::invalid_option, "set_allocator: allocate and deallocate must both be set (or both null)");
  detail::State& s = detail::state();
  std::lock_guard<std::mutex> lock(s.mutex);
  const int calls = s.calls.load(std::memory_order_acquire);
  if (calls != 0)
    return Status(StatusCode::invalid_option, "set_allocator: refused while %d call%s running", calls,
                  calls == 1 ? " is" : "s are");
  if (s.bytes != 0)
    return Status(StatusCode::invalid_option,
                  "set_allocator: refused while the library holds %llu bytes from the current allocator "
                  "(call release_memory() and destroy every Image first)",
                  static_cast<unsigned long long>(s.bytes));
  s.allocator = allocator != nullptr ? *allocator : Allocator{};
  return Status();
}

void release_memory() noexcept {
  detail::release_cached_scratch();
  detail::release_thread_pool();
}

std::size_t memory_in_use() noexcept {
  detail::State& s = detail::state();
  std::lock_guard<std::mutex> lock(s.mutex);
  return s.bytes;
}

}  // namespace reproject
