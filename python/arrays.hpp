// NumPy arrays as the library's views, without copying (python/sources.cpp, targets.cpp, ...).
//
// The library reads planes whose pixels are consecutive floats and whose rows start `stride`
// floats apart, one interleaved RGBA plane (4 consecutive floats a pixel), or an engine-native
// buffer (formats.hpp: packed RGBA colour, D16 / D24S8 / packed RGBA8 depth) whose pixels are
// consecutive and whose rows start any number of bytes apart. An array is passed as such a view
// when its strides say it is one; otherwise it is refused with a ValueError that names the array,
// its shape and strides, and the fix. The one exception is H x W x C colour with
// C = 2 or 3 packed pixel after pixel (what Pillow gives): the library has no such layout, so it
// is copied once into planes (documented in warp's docstring).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>

#include "reproject/image.hpp"

namespace reproject::python {

namespace py = pybind11;

// How colour is laid out in its array.
enum class ColorForm {
  plane,  // H x W: one channel
  hwc,    // H x W x C
  chw,    // C x H x W
};

std::string describe(const py::array& a);  // "float32 array of shape (2, 3) and strides (12, 4)"

// Whether `a` holds `dtype` in the machine's byte order (a big-endian array is not).
bool has_dtype(const py::array& a, const py::dtype& dtype);
// TypeError unless `a` holds native float32 (uint8 for `bytes`).
void require_dtype(const py::array& a, const char* name, bool bytes = false);
// ValueError unless `a` can be written.
void require_writeable(const py::array& a, const char* name);

// One plane from axes (row_axis, column_axis) of `a`, starting `offset_bytes` into its data.
// ValueError when the columns are not consecutive elements or a stride is not a whole number of
// elements. The row stride is passed as it is: the library itself refuses one shorter than a row.
template <class T>
PlaneView<T> plane_view(const py::array& a, int row_axis, int column_axis, std::ptrdiff_t offset_bytes,
                        const char* name);

// The pixels of an (H, W) array, or of an (H, W, C) one whose C channels are consecutive (one
// pixel), as bytes: data, width and height in pixels, row stride in bytes (any number: the
// engine formats' rows need no alignment). ValueError when the channels or the columns are not
// consecutive. For engine-native buffers, and for float RGBA (which then checks whole floats).
PlaneView<std::uint8_t> pixel_rows(const py::array& a, const char* name);

// The colour's form, from its shape and the depth's (height, width). ValueError when it fits none.
ColorForm color_form(const py::array& color, int height, int width, const char* name);
int channel_count(const py::array& color, ColorForm form);

// The colour as the library's view: planar, or interleaved RGBA for H x W x 4 with packed pixels.
// False (and nothing set) for H x W x C whose pixels are packed but C != 4: the caller copies.
template <class View>
bool color_view(const py::array& color, ColorForm form, const char* name, View* out);

}  // namespace reproject::python
