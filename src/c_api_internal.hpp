// Internal: what the files of the C interface (include/reproject/reproject.h) share. Each part
// converts the plain C structs and values to the C++ ones and calls the C++ API, so C and C++
// compute the same thing bit for bit; nothing throws and nothing allocates.
//   src/c_api_views.cpp   the C structs of images and buffers -> the C++ views
//   src/c_api_models.cpp  decoders, parallax models, options, the cancel flag, instruction sets
//   src/c_api_warp.cpp    the last error's message, the names, the warp entry points
// Not installed.
#pragma once

#include <cstdint>

#include "reproject/reproject.h"
#include "reproject/reproject.hpp"

namespace reproject {
namespace c_abi {

// Values of the C constants are the C++ enumerators' (every file here casts between them):
// checked here so that neither side drifts.
static_assert(REPROJECT_INVALID_OPTION == static_cast<int>(StatusCode::invalid_option) &&
                  REPROJECT_CANCELLED == static_cast<int>(StatusCode::cancelled) &&
                  REPROJECT_OUT_OF_MEMORY == static_cast<int>(StatusCode::out_of_memory),
              "status codes");
static_assert(REPROJECT_METHOD_EXACT == static_cast<int>(Method::exact), "methods");
static_assert(REPROJECT_ARCH_AVX512 == static_cast<int>(Arch::avx512) &&
                  REPROJECT_ARCH_NEON == static_cast<int>(Arch::neon) && kArchCount == 5,
              "arches");
static_assert(REPROJECT_PIXEL_CLIPPED == static_cast<int>(PixelStatus::clipped), "pixel statuses");
static_assert(REPROJECT_FILL_NONE == static_cast<int>(HoleFill::none), "hole fills");
static_assert(REPROJECT_EDGE_MIRROR == static_cast<int>(EdgeMode::mirror), "edge modes");
static_assert(REPROJECT_DEPTH_DISPARITY == static_cast<int>(DepthEncoding::disparity), "encodings");
static_assert(REPROJECT_CENTRE_TO_RIGHT == static_cast<int>(EyeDirection::centre_to_right), "directions");
static_assert(REPROJECT_LAYOUT_INTERLEAVED_RGBA == static_cast<int>(ColorLayout::interleaved_rgba), "layouts");
// Formats: every value, as the mapping casts them (a swapped pair would otherwise go unnoticed).
static_assert(REPROJECT_COLOR_FLOAT32 == static_cast<int>(ColorFormat::float32) &&
                  REPROJECT_COLOR_RGBA8 == static_cast<int>(ColorFormat::rgba8) &&
                  REPROJECT_COLOR_RGBA8_SRGB == static_cast<int>(ColorFormat::rgba8_srgb) &&
                  REPROJECT_COLOR_RGBA16F == static_cast<int>(ColorFormat::rgba16f) &&
                  REPROJECT_COLOR_RGBA16F + 1 == kColorFormatCount,
              "colour formats");
static_assert(REPROJECT_DEPTH_FORMAT_FLOAT32 == static_cast<int>(DepthFormat::float32) &&
                  REPROJECT_DEPTH_FORMAT_UNORM16 == static_cast<int>(DepthFormat::unorm16) &&
                  REPROJECT_DEPTH_FORMAT_UNORM24_S8 == static_cast<int>(DepthFormat::unorm24_s8) &&
                  REPROJECT_DEPTH_FORMAT_S8_UNORM24 == static_cast<int>(DepthFormat::s8_unorm24) &&
                  REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR == static_cast<int>(DepthFormat::rgba8_packed_linear) &&
                  REPROJECT_DEPTH_FORMAT_RGBA8_PACKED_LINEAR + 1 == kDepthFormatCount,
              "depth formats");

// Records a failure's message for reproject_last_error_message() and returns its code
// (src/c_api_warp.cpp).
reproject_status report(const Status& status) noexcept;

// C's int32 values as the C++ enums, whose underlying type is uint8_t: a value beyond it must not
// wrap onto a valid one (257 would become 1, "standard"). Unknown values inside 0..255 are refused
// (or named "unknown") by the C++ side; those beyond are handled before the cast.
inline bool fits_enum(std::int32_t value) noexcept { return value >= 0 && value <= 255; }

// src/c_api_views.cpp: the C structs to the C++ views (one function per struct). The float-only
// structs are the _buffers ones with no pixels and no depth buffer; a _buffers struct is itself.
Status source_of(const reproject_source_buffers& s, const char* name, SourceView* out) noexcept;
Status target_of(const reproject_target_buffers& t, const char* name, TargetView* out) noexcept;
reproject_source_buffers buffers_of(const reproject_source& s) noexcept;
reproject_target_buffers buffers_of(const reproject_target& t) noexcept;
inline const reproject_source_buffers& buffers_of(const reproject_source_buffers& s) noexcept { return s; }
inline const reproject_target_buffers& buffers_of(const reproject_target_buffers& t) noexcept { return t; }

// src/c_api_models.cpp: an encoding beyond the enum is invalid_decoder, naming the value passed.
Status check_encoding(std::int32_t encoding) noexcept;
DepthDecoder decoder_of(const reproject_decoder& d) noexcept;
// Copies the fields the caller's struct holds (struct_size) over the defaults, range-checked.
Status options_of(const reproject_options* c, Options* out) noexcept;

}  // namespace c_abi
}  // namespace reproject
