// Internal: the library's one way to take memory (docs/BEHAVIOUR.md, "Memory"): every byte goes
// through the host's allocator (reproject::set_allocator, reproject_set_allocator) or the default,
// and failure is a null pointer, never an exception. Defined in src/memory.cpp; declared here so
// that the kernels' row scratch (kernels/frame.hpp) can hold it without reaching up into src/.
#pragma once

#include <cstddef>
#include <cstring>
#include <new>
#include <type_traits>

namespace reproject::detail {

// Cache-line alignment for every buffer the library allocates: whole-vector loads and stores of
// any width never straddle a line because of where a buffer happened to start.
constexpr std::size_t kBufferAlignment = 64;

// `size` bytes aligned to `alignment` (a power of two), or null when the allocator has none.
void* allocate(std::size_t size, std::size_t alignment) noexcept;
// Gives back what allocate() returned, with the same size and alignment. Null is ignored.
void deallocate(void* pointer, std::size_t size, std::size_t alignment) noexcept;

// A T constructed in memory from allocate() (null when out of memory), and its destruction.
template <class T>
T* create() noexcept {
  static_assert(std::is_nothrow_default_constructible<T>::value, "library objects are built without exceptions");
  void* memory = allocate(sizeof(T), alignof(T) > kBufferAlignment ? alignof(T) : kBufferAlignment);
  return memory != nullptr ? new (memory) T() : nullptr;
}
template <class T>
void destroy(T* object) noexcept {
  if (object == nullptr) return;
  object->~T();
  deallocate(object, sizeof(T), alignof(T) > kBufferAlignment ? alignof(T) : kBufferAlignment);
}

// A growable array of trivially copyable T in allocate()'s memory, for scratch: growing keeps no
// contents (the new elements are zero), and a buffer that is large enough never allocates.
template <class T>
class Buffer {
  static_assert(std::is_trivially_copyable<T>::value, "Buffer holds plain values");

 public:
  Buffer() noexcept = default;
  ~Buffer() { reset(); }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  T* data() noexcept { return data_; }
  const T* data() const noexcept { return data_; }
  std::size_t size() const noexcept { return size_; }
  T& operator[](std::size_t i) noexcept { return data_[i]; }
  const T& operator[](std::size_t i) const noexcept { return data_[i]; }

  // At least `count` elements, all zero if it had to grow. False (the buffer unchanged) when the
  // allocator is out of memory or the byte count would overflow.
  [[nodiscard]] bool reserve(std::size_t count) noexcept {
    if (count <= size_) return true;
    if (count > static_cast<std::size_t>(-1) / sizeof(T)) return false;
    void* memory = allocate(count * sizeof(T), kBufferAlignment);
    if (memory == nullptr) return false;
    std::memset(memory, 0, count * sizeof(T));
    reset();
    data_ = static_cast<T*>(memory);
    size_ = count;
    return true;
  }
  // Gives the memory back.
  void reset() noexcept {
    deallocate(data_, size_ * sizeof(T), kBufferAlignment);
    data_ = nullptr;
    size_ = 0;
  }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace reproject::detail
