/* reproject's C interface: the host's memory (included by reproject/reproject.h, whose conventions apply). */
#ifndef REPROJECT_MEMORY_H
#define REPROJECT_MEMORY_H

#include <stddef.h>

#include "reproject/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The host's memory (C++ reproject::Allocator, reproject/memory.hpp; docs/BEHAVIOUR.md "Memory").
 * Every byte the library takes (its thread pool, each thread's row scratch, SSIM's rows, the
 * parallax budget's sort) comes from allocate and goes back to deallocate, with the size and
 * alignment it was asked for (alignment a power of two, at most 4096). allocate returns NULL when
 * it has no memory: the call that asked returns REPROJECT_OUT_OF_MEMORY and keeps nothing. Both
 * may be called from any thread, the library's pool threads included, and must not call into the
 * library; user is passed to both as it is (it may be NULL). */
typedef struct reproject_allocator {
  void* (*allocate)(void* user, size_t size, size_t alignment);
  void (*deallocate)(void* user, void* pointer, size_t size, size_t alignment);
  void* user;
} reproject_allocator;
/* Makes *allocator the library's (the struct is copied); NULL: the default (C++ operator new).
 * Refused with REPROJECT_INVALID_OPTION, changing nothing, while the library holds memory from the
 * current allocator (call reproject_release_memory() first) or a call is running, and when only
 * one of allocate and deallocate is set. */
reproject_status reproject_set_allocator(const reproject_allocator* allocator);
/* Gives back every cached scratch set and stops and joins the pool's threads: afterwards the
 * library holds no memory (reproject_memory_in_use() is 0) when no call was running. The next call
 * allocates afresh. A program that calls only with options.threads = 1 or a reproject_parallel_for
 * never starts a thread. */
void reproject_release_memory(void);
/* Bytes the library holds from the allocator now. */
size_t reproject_memory_in_use(void);

#ifdef __cplusplus
}
#endif

#endif /* REPROJECT_MEMORY_H */
