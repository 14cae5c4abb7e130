// Internal: the bytes a strided view covers, computed with overflow checks, and whether two views
// touch a common byte. The one implementation behind every boundary's validation (reproject.cpp,
// stereo_checks.hpp, and through them the C interface and the Python module); docs/ERRORS.md lists
// the messages. Not installed.
#pragma once

#include <cstddef>
#include <cstdint>

#include "reproject/image.hpp"
#include "reproject/status.hpp"

namespace reproject {
namespace detail {

// A view's rows as address ranges: row y covers [first + y * stride, first + y * stride + row).
// Made by check_view_bytes(), which guarantees stride >= row and that the last row ends inside
// the address space, so that every sum below is exact.
struct ViewBytes {
  std::uintptr_t first = 0;
  std::uint64_t rows = 0;    // 0: an empty view, which touches nothing
  std::uint64_t row = 0;     // bytes of one row
  std::uint64_t stride = 0;  // bytes between row starts
};

// Checks the rows of a view of `width` x `height` pixels (both >= 0, checked by the caller),
// `per_pixel` elements of `element_bytes` each, rows `stride` elements apart:
//  * the stride holds a row (stride >= width * per_pixel; invalid_stride, "smaller than the row");
//  * for a non-empty view, data is a multiple of element_bytes (invalid_stride, "not aligned");
//  * for a non-empty view, the stride in bytes and the extent, (height - 1) x stride + row
//    bytes, are offsets the kernels can form (they fit ptrdiff_t; invalid_stride, "overflows");
//  * data + extent does not run past the end of the address space (invalid_size).
// Messages start with `name` and give the stride in `unit` ("elements" or "bytes"). On success
// `out` (if not null) holds the view's rows; null data or an empty size give no rows.
Status check_view_bytes(const void* data, int width, int height, std::ptrdiff_t stride, int per_pixel,
                        int element_bytes, const char* name, const char* unit, ViewBytes* out = nullptr) noexcept;

template <class T>
Status check_view_bytes(const PlaneView<T>& view, int per_pixel, const char* name, const char* unit,
                        ViewBytes* out = nullptr) noexcept {
  return check_view_bytes(view.data, view.width, view.height, view.stride, per_pixel, static_cast<int>(sizeof(T)),
                          name, unit, out);
}

// The rows of a view that check_view_bytes() accepted (no rows for null data or an empty size).
template <class T>
ViewBytes view_bytes(const PlaneView<T>& view, int per_pixel) noexcept {
  ViewBytes bytes;
  if (view.data == nullptr || view.width <= 0 || view.height <= 0) return bytes;
  bytes.first = reinterpret_cast<std::uintptr_t>(view.data);
  bytes.rows = static_cast<std::uint64_t>(view.height);
  bytes.row = static_cast<std::uint64_t>(view.width) * static_cast<std::uint64_t>(per_pixel) * sizeof(T);
  bytes.stride = static_cast<std::uint64_t>(view.stride) * sizeof(T);
  return bytes;
}

// Whether a row of `a` and a row of `b` share a byte. The bytes between rows belong to neither:
// the left and right halves of one side-by-side buffer do not touch. O(rows of the shorter view).
bool views_touch(const ViewBytes& a, const ViewBytes& b) noexcept;

}  // namespace detail
}  // namespace reproject
