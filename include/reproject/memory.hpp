// The host's memory for the library (docs/BEHAVIOUR.md, "Memory"). Every byte the library takes
// (the thread pool, each thread's row scratch, SSIM's rows, the parallax budget's sort, Image)
// comes from one allocator, the host's if it sets one, and goes back to it. Out of memory is a
// Status (StatusCode::out_of_memory), never an exception or an abort.
#pragma once

#include <cstddef>

#include "reproject/status.hpp"

namespace reproject {

// The host's allocator. allocate returns `size` bytes aligned to `alignment` (a power of two, at
// most 4096), or null when it has none: the call that asked then returns out_of_memory and keeps
// nothing it took. deallocate gets back exactly what allocate returned, with the same size and
// alignment. Both may be called from any thread, including the library's pool threads, and must
// not call into the library. `user` is passed to both unchanged.
struct Allocator {
  void* (*allocate)(void* user, std::size_t size, std::size_t alignment) = nullptr;
  void (*deallocate)(void* user, void* pointer, std::size_t size, std::size_t alignment) = nullptr;
  void* user = nullptr;
};

// Makes `allocator` the library's (a copy of the struct is kept; null: the default, global
// operator new and delete). Refused with invalid_option, changing nothing, while the library holds
// any memory from the current allocator (cached scratch, the pool, an Image not yet destroyed) or
// a call is running: release_memory() first, and destroy your Images. Also invalid_option when
// only one of the two functions is set.
Status set_allocator(const Allocator* allocator) noexcept;

// Gives back every cached scratch set and stops and joins the pool's threads, so that the library
// holds nothing (but the Images you own). What a call running at the same time uses is left to
// it; call this when no call runs to release everything. The next call allocates afresh.
void release_memory() noexcept;

// Bytes the library holds from the allocator now (cached scratch, the pool, live Images).
std::size_t memory_in_use() noexcept;

}  // namespace reproject
