// The C interface's memory functions (include/reproject/reproject.h) over reproject/memory.hpp.
#include "reproject/memory.hpp"
#include "reproject/reproject.h"
#include "src/c_api_internal.hpp"

extern "C" {

reproject_status reproject_set_allocator(const reproject_allocator* allocator) {
  if (allocator == nullptr) return reproject::c_abi::report(reproject::set_allocator(nullptr));
  reproject::Allocator a;
  a.allocate = allocator->allocate;
  a.deallocate = allocator->deallocate;
  a.user = allocator->user;
  return reproject::c_abi::report(reproject::set_allocator(&a));
}

void reproject_release_memory(void) { reproject::release_memory(); }

size_t reproject_memory_in_use(void) { return reproject::memory_in_use(); }

}  // extern "C"
