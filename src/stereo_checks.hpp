// Internal: the checks and the depth reading that the functions of include/reproject/stereo.hpp
// share (src/stereo_*.cpp), written once. Every message starts with the public function's name
// (docs/ERRORS.md). Not installed.
#pragma once

#include <cstdio>
#include <limits>

#include "reproject/depth.hpp"
#include "reproject/image.hpp"
#include "reproject/parallax.hpp"
#include "reproject/status.hpp"
#include "src/view_bounds.hpp"

namespace reproject {
namespace detail {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A failed status with the calling function's name in front of its message; ok stays ok.
Status in_function(const char* function, const Status& status) noexcept;

// A plane that may be empty (then its pointer is not needed); otherwise non-null, with a stride
// that holds its rows and an extent that fits the address space (src/view_bounds.hpp).
template <class T>
Status check_plane(const PlaneView<T>& plane, const char* function, const char* name) noexcept {
  if (plane.width < 0 || plane.height < 0)
    return Status(StatusCode::invalid_size, "%s: %s has a negative size %dx%d", function, name, plane.width,
                  plane.height);
  if (plane.width == 0 || plane.height == 0) return Status();
  if (plane.data == nullptr) return Status(StatusCode::null_pointer, "%s: %s data is null", function, name);
  char label[96];
  std::snprintf(label, sizeof label, "%s: %s", function, name);
  return check_view_bytes(plane, 1, label, "elements");
}

template <class T, class U>
Status check_same_size(const PlaneView<T>& plane, const PlaneView<U>& reference, const char* function,
                       const char* name, const char* reference_name) noexcept {
  if (plane.width != reference.width || plane.height != reference.height)
    return Status(StatusCode::size_mismatch, "%s: %s is %dx%d, %s is %dx%d", function, name, plane.width,
                  plane.height, reference_name, reference.width, reference.height);
  return Status();
}

// Two checked planes share a byte of their rows (the bytes between rows are no one's: the halves
// of one side-by-side buffer do not overlap).
template <class T, class U>
bool planes_overlap(const PlaneView<T>& p, const PlaneView<U>& q) noexcept {
  return views_touch(view_bytes(p, 1), view_bytes(q, 1));
}

// A finite separation >= 0 and a finite convergence > 0 (docs/DESIGN.md §4).
Status check_camera(const StereoCamera& camera, const char* function) noexcept;

// A valid decoder that yields inverse depth (not a disparity map, whose "w" is no depth).
Status check_depth_decoder(const DepthDecoder& decoder, const char* function) noexcept;

// The inverse depth the kernels use for a stored value (docs/BEHAVIOUR.md "Parallax decode"):
// values that decode to NaN or to w < 0 are farther than infinity, read as w = 0.
double readable_inverse_depth(const DepthDecoder& decoder, float stored, bool* unreadable) noexcept;

}  // namespace detail
}  // namespace reproject
