#include "arrays.hpp"

#include <cstdint>
#include <sstream>

namespace reproject::python {

std::string describe(const py::array& a) {
  std::ostringstream s;
  s << py::str(a.dtype()).cast<std::string>() << " array of shape (";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
  s << (a.ndim() == 1 ? ",)" : ")") << " and strides (";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.strides(i);
  s << (a.ndim() == 1 ? ",)" : ")");
  return s.str();
}

bool has_dtype(const py::array& a, const py::dtype& dtype) {
  // dtype equality includes the byte order: a big-endian float32 is not float32.
  return dtype.attr("__eq__")(a.dtype()).cast<bool>();
}

void require_dtype(const py::array& a, const char* name, bool bytes) {
  if (!has_dtype(a, bytes ? py::dtype::of<std::uint8_t>() : py::dtype::of<float>())) {
    throw py::type_error(std::string(name) + ": expected a " + (bytes ? "uint8" : "float32") + " array, got " +
                         describe(a) + (bytes ? "" : " (convert with .astype(numpy.float32))"));
  }
}

void require_writeable(const py::array& a, const char* name) {
  if (!a.writeable()) throw py::value_error(std::string(name) + ": the array is read-only");
}

namespace {

[[noreturn]] void not_a_view(const py::array& a, const char* name, const char* why) {
  throw py::value_error(std::string(name) + ": " + describe(a) + " cannot be passed without a copy (" + why +
                        "); pass numpy.ascontiguousarray(" + name + ")");
}

// The rows of axes (row_axis, column_axis) of `a`, `pixel_bytes` a column, as bytes. The one rule
// for every view: columns must be consecutive; the row stride is passed as it is (the library
// refuses one shorter than a row, or negative).
PlaneView<std::uint8_t> rows_of(const py::array& a, int row_axis, int column_axis, std::ptrdiff_t pixel_bytes,
                                std::ptrdiff_t offset_bytes, const char* name, const char* unit) {
  const py::ssize_t height = a.shape(row_axis), width = a.shape(column_axis);
  // One column needs no column stride; one row needs no row stride (numpy may give any value, and
  // gives 0 for an empty array, which has nothing to read: the library accepts an empty frame).
  if (width > 1 && a.size() > 0 && a.strides(column_axis) != pixel_bytes) {
    not_a_view(a, name, (std::string("its columns are not consecutive ") + unit).c_str());
  }
  if (height > INT32_MAX || width > INT32_MAX) {
    throw py::value_error(std::string(name) + ": " + describe(a) + " has more than 2147483647 rows or columns, the "
                          "most the library takes (and at most 4194304 columns)");
  }
  const std::ptrdiff_t row_stride = height <= 1 ? width * pixel_bytes : a.strides(row_axis);
  // Rows run forwards, each after the previous one's pixels: a negative row stride (a[::-1]) or
  // rows that overlap (as_strided) cannot be passed as they are, whatever the library would say.
  if (height > 1 && a.size() > 0 && row_stride < width * pixel_bytes) {
    const std::string why = std::string(row_stride < 0 ? "its rows run backwards" : "its rows overlap") +
                            ": row stride " + std::to_string(row_stride) + " bytes, a row is " +
                            std::to_string(width * pixel_bytes) + " bytes";
    not_a_view(a, name, why.c_str());
  }
  auto* data = static_cast<std::uint8_t*>(const_cast<void*>(a.data())) + offset_bytes;
  return PlaneView<std::uint8_t>{data, static_cast<int>(width), static_cast<int>(height), row_stride};
}

}  // namespace

template <class T>
PlaneView<T> plane_view(const py::array& a, int row_axis, int column_axis, std::ptrdiff_t offset_bytes,
                        const char* name) {
  const std::ptrdiff_t element = static_cast<std::ptrdiff_t>(sizeof(T));
  const PlaneView<std::uint8_t> rows = rows_of(a, row_axis, column_axis, element, offset_bytes, name, "elements");
  if (rows.stride % element != 0 || reinterpret_cast<std::uintptr_t>(rows.data) % alignof(T) != 0) {
    not_a_view(a, name, "its data or strides are not aligned to whole elements");
  }
  return PlaneView<T>{reinterpret_cast<T*>(rows.data), rows.width, rows.height, rows.stride / element};
}

PlaneView<std::uint8_t> pixel_rows(const py::array& a, const char* name) {
  const std::ptrdiff_t item = a.itemsize();
  std::ptrdiff_t pixel = item;
  if (a.ndim() == 3) {
    if (a.shape(2) > 1 && a.size() > 0 && a.strides(2) != item) {
      not_a_view(a, name, "the channels of its pixels are not consecutive");
    }
    pixel = item * a.shape(2);
  }
  return rows_of(a, 0, 1, pixel, 0, name, "pixels");
}

template PlaneView<const float> plane_view(const py::array&, int, int, std::ptrdiff_t, const char*);
template PlaneView<float> plane_view(const py::array&, int, int, std::ptrdiff_t, const char*);
template PlaneView<std::uint8_t> plane_view(const py::array&, int, int, std::ptrdiff_t, const char*);

ColorForm color_form(const py::array& color, int height, int width, const char* name) {
  if (color.ndim() == 2 && color.shape(0) == height && color.shape(1) == width) return ColorForm::plane;
  if (color.ndim() == 3) {
    // H x W x C is tried first: it is what images usually are, and it decides the rare shapes
    // that fit both (e.g. 3 x 3 x 3 with a 3 x 3 depth).
    if (color.shape(0) == height && color.shape(1) == width && color.shape(2) >= 1 && color.shape(2) <= 4)
      return ColorForm::hwc;
    if (color.shape(1) == height && color.shape(2) == width && color.shape(0) >= 1 && color.shape(0) <= 4)
      return ColorForm::chw;
  }
  throw py::value_error(std::string(name) + ": " + describe(color) + " does not fit a depth of shape (" +
                        std::to_string(height) + ", " + std::to_string(width) +
                        "): expected (H, W), (H, W, C) or (C, H, W) with C = 1..4");
}

int channel_count(const py::array& color, ColorForm form) {
  switch (form) {
    case ColorForm::plane: return 1;
    case ColorForm::hwc: return static_cast<int>(color.shape(2));
    case ColorForm::chw: return static_cast<int>(color.shape(0));
  }
  return 0;
}

template <class View>
bool color_view(const py::array& color, ColorForm form, const char* name, View* out) {
  using T = std::remove_reference_t<decltype(*View{}.plane[0].data)>;
  View view;
  if (form == ColorForm::plane) {
    view.channels = 1;
    view.plane[0] = plane_view<T>(color, 0, 1, 0, name);
    *out = view;
    return true;
  }
  const int channels = channel_count(color, form);
  const int channel_axis = form == ColorForm::hwc ? 2 : 0;
  const int row_axis = form == ColorForm::hwc ? 0 : 1;
  const std::ptrdiff_t element = sizeof(float);
  if (form == ColorForm::hwc && color.shape(1) > 1 && color.strides(1) != element) {
    // Pixels packed one after another: interleaved RGBA when there are 4 floats per pixel.
    if (channels == 4 && color.strides(1) == 4 * element && color.strides(2) == element) {
      view.layout = ColorLayout::interleaved_rgba;
      view.channels = 4;
      const PlaneView<std::uint8_t> rows = pixel_rows(color, name);
      if (rows.stride % element != 0 || reinterpret_cast<std::uintptr_t>(rows.data) % alignof(float) != 0) {
        not_a_view(color, name, "its data or row stride is not aligned to whole floats");
      }
      view.plane[0] = PlaneView<T>{reinterpret_cast<T*>(rows.data), rows.width, rows.height, rows.stride / element};
      *out = view;
      return true;
    }
    if (color.strides(1) == channels * element && color.strides(2) == element && channels != 4) return false;
  }
  view.channels = channels;
  for (int c = 0; c < channels; ++c) {
    view.plane[c] = plane_view<T>(color, row_axis, 1 + (form == ColorForm::chw ? 1 : 0),
                                  static_cast<std::ptrdiff_t>(c) * color.strides(channel_axis), name);
  }
  *out = view;
  return true;
}

template bool color_view(const py::array&, ColorForm, const char*, ColorView*);
template bool color_view(const py::array&, ColorForm, const char*, MutableColorView*);

}  // namespace reproject::python
