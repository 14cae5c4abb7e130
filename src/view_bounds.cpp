#include "src/view_bounds.hpp"

#include <algorithm>
#include <cstdint>

namespace reproject {
namespace detail {

Status check_view_bytes(const void* data, int width, int height, std::ptrdiff_t stride, int per_pixel,
                        int element_bytes, const char* name, const char* unit, ViewBytes* out) noexcept {
  if (out != nullptr) *out = ViewBytes{};
  // width <= 2^31 and per_pixel <= 8: the row fits any 64-bit type.
  const std::int64_t row_elements = static_cast<std::int64_t>(width) * per_pixel;
  if (static_cast<std::int64_t>(stride) < row_elements)
    return Status(StatusCode::invalid_stride, "%s: stride %td is smaller than the row (%td %s)", name, stride,
                  static_cast<std::ptrdiff_t>(row_elements), unit);
  if (width == 0 || height == 0) return Status();
  // Elements are read through typed pointers (a float plane's floats): a base between two elements
  // is no such pointer (the C interface can be handed one; UBSan reports the load).
  if (reinterpret_cast<std::uintptr_t>(data) % static_cast<std::uintptr_t>(element_bytes) != 0)
    return Status(StatusCode::invalid_stride, "%s: data 0x%llx is not aligned to its %d-byte elements", name,
                  static_cast<unsigned long long>(reinterpret_cast<std::uintptr_t>(data)), element_bytes);

  // The kernels address row y as data + y * stride in ptrdiff_t (bytes for the engine formats,
  // and the float depth plane's stride is taken in bytes too), so the stride in bytes and the
  // offset of the last row's end must both be ptrdiff_t values: no product below can overflow.
  const std::uint64_t max_offset = static_cast<std::uint64_t>(PTRDIFF_MAX);
  const std::uint64_t element = static_cast<std::uint64_t>(element_bytes);
  if (static_cast<std::uint64_t>(stride) > max_offset / element)
    return Status(StatusCode::invalid_stride, "%s: stride %td %s: the stride in bytes overflows", name, stride, unit);
  const std::uint64_t stride_bytes = static_cast<std::uint64_t>(stride) * element;
  const std::uint64_t row_bytes = static_cast<std::uint64_t>(row_elements) * element;
  const std::uint64_t last_row = static_cast<std::uint64_t>(height) - 1;
  if (last_row > 0 && last_row > (max_offset - row_bytes) / stride_bytes)
    return Status(StatusCode::invalid_stride, "%s: stride %td %s: the view's extent overflows (%d rows)", name, stride,
                  unit, height);
  const std::uint64_t extent = last_row * stride_bytes + row_bytes;
  const std::uint64_t first = static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(data));
  // The last byte's address must be representable and the end (one past it) too.
  if (data != nullptr && extent > static_cast<std::uint64_t>(UINTPTR_MAX) - first)
    return Status(StatusCode::invalid_size, "%s: the view's %llu bytes from 0x%llx run past the end of the address space",
                  name, static_cast<unsigned long long>(extent), static_cast<unsigned long long>(first));
  if (out != nullptr && data != nullptr) {
    out->first = static_cast<std::uintptr_t>(first);
    out->rows = static_cast<std::uint64_t>(height);
    out->row = row_bytes;
    out->stride = stride_bytes;
  }
  return Status();
}

namespace {

std::uint64_t end_of(const ViewBytes& v) noexcept { return v.first + (v.rows - 1) * v.stride + v.row; }

}  // namespace

bool views_touch(const ViewBytes& a, const ViewBytes& b) noexcept {
  if (a.rows == 0 || b.rows == 0 || a.row == 0 || b.row == 0) return false;
  if (end_of(a) <= b.first || end_of(b) <= a.first) return false;
  // Walk the rows of the view with fewer rows. For each, the other view's rows are disjoint and
  // in address order (stride >= row), so only the last of them that starts before this row ends
  // can reach into it: an earlier one ends earlier still, a later one starts at or after its end.
  const ViewBytes& walked = a.rows <= b.rows ? a : b;
  const ViewBytes& other = a.rows <= b.rows ? b : a;
  const std::uint64_t other_end = end_of(other);
  for (std::uint64_t i = 0; i < walked.rows; ++i) {
    const std::uint64_t begin = walked.first + i * walked.stride;
    const std::uint64_t end = begin + walked.row;
    if (begin >= other_end) break;
    if (end <= other.first) continue;
    const std::uint64_t j = std::min(other.rows - 1, (end - 1 - other.first) / other.stride);
    if (other.first + j * other.stride + other.row > begin) return true;
  }
  return false;
}

}  // namespace detail
}  // namespace reproject
