// Every public enum's names, in one table each (src/names.hpp), and the public to_string and
// parse_* functions over them.
#include "src/names.hpp"

#include "reproject/formats.hpp"
#include "reproject/reproject.hpp"
#include "reproject/stereo.hpp"

namespace reproject {

using detail::EnumName;
using detail::name_of;
using detail::parse_name;

// Each enum: its table (internal linkage, as every namespace-scope constexpr), a check that every
// value has a name where the header has a count, and its functions.

constexpr EnumName<Method> kMethods[] = {
    {Method::scanline, "scanline"}, {Method::march16, "march16"}, {Method::single, "single"},
    {Method::secant, "secant"},     {Method::exact, "exact"},
};
static_assert(sizeof kMethods / sizeof kMethods[0] == kMethodCount, "every Method has a name");
const char* to_string(Method method) noexcept { return name_of(kMethods, method); }
bool parse_method(const char* name, Method* out) noexcept { return parse_name(kMethods, name, out); }

constexpr EnumName<Arch> kArches[] = {
    {Arch::scalar, "scalar"}, {Arch::sse, "sse"}, {Arch::avx2, "avx2"}, {Arch::avx512, "avx512"}, {Arch::neon, "neon"},
};
static_assert(sizeof kArches / sizeof kArches[0] == kArchCount, "every Arch has a name");
const char* to_string(Arch arch) noexcept { return name_of(kArches, arch); }
bool parse_arch(const char* name, Arch* out) noexcept { return parse_name(kArches, name, out); }

constexpr EnumName<HoleFill> kHoleFills[] = {
    {HoleFill::background, "background"}, {HoleFill::foreground, "foreground"}, {HoleFill::none, "none"},
};
static_assert(sizeof kHoleFills / sizeof kHoleFills[0] == kHoleFillCount, "every HoleFill has a name");
const char* to_string(HoleFill fill) noexcept { return name_of(kHoleFills, fill); }
bool parse_hole_fill(const char* name, HoleFill* out) noexcept { return parse_name(kHoleFills, name, out); }

constexpr EnumName<EdgeMode> kEdgeModes[] = {
    {EdgeMode::clamp, "clamp"}, {EdgeMode::none, "none"}, {EdgeMode::black, "black"}, {EdgeMode::mirror, "mirror"},
};
static_assert(sizeof kEdgeModes / sizeof kEdgeModes[0] == kEdgeModeCount, "every EdgeMode has a name");
const char* to_string(EdgeMode edge) noexcept { return name_of(kEdgeModes, edge); }
bool parse_edge_mode(const char* name, EdgeMode* out) noexcept { return parse_name(kEdgeModes, name, out); }

constexpr EnumName<DepthEncoding> kEncodings[] = {
    {DepthEncoding::linear, "linear"},     {DepthEncoding::standard, "standard"},
    {DepthEncoding::gl_ndc, "gl_ndc"},     {DepthEncoding::reversed, "reversed"},
    {DepthEncoding::reversed_infinite, "reversed_infinite"},
    {DepthEncoding::infinite, "infinite"}, {DepthEncoding::disparity, "disparity"},
};
static_assert(sizeof kEncodings / sizeof kEncodings[0] == kDepthEncodingCount, "every DepthEncoding has a name");
const char* to_string(DepthEncoding encoding) noexcept { return name_of(kEncodings, encoding); }
bool parse_encoding(const char* name, DepthEncoding* out) noexcept { return parse_name(kEncodings, name, out); }

// Hyphens are the names; underscores are accepted too (the C++ spelling).
constexpr EnumName<EyeDirection> kDirections[] = {
    {EyeDirection::left_to_right, "left-to-right"},     {EyeDirection::right_to_left, "right-to-left"},
    {EyeDirection::centre_to_left, "centre-to-left"},   {EyeDirection::centre_to_right, "centre-to-right"},
    {EyeDirection::left_to_right, "left_to_right"},     {EyeDirection::right_to_left, "right_to_left"},
    {EyeDirection::centre_to_left, "centre_to_left"},   {EyeDirection::centre_to_right, "centre_to_right"},
};
static_assert(sizeof kDirections / sizeof kDirections[0] == 2 * kEyeDirectionCount, "every EyeDirection has a name");
const char* to_string(EyeDirection direction) noexcept { return name_of(kDirections, direction); }
bool parse_direction(const char* name, EyeDirection* out) noexcept { return parse_name(kDirections, name, out); }

constexpr EnumName<ColorFormat> kColorFormats[] = {
    {ColorFormat::float32, "float32"}, {ColorFormat::rgba8, "rgba8"}, {ColorFormat::rgba8_srgb, "rgba8_srgb"},
    {ColorFormat::rgba16f, "rgba16f"},
};
static_assert(sizeof kColorFormats / sizeof kColorFormats[0] == kColorFormatCount, "every ColorFormat has a name");
const char* to_string(ColorFormat format) noexcept { return name_of(kColorFormats, format); }
bool parse_color_format(const char* name, ColorFormat* out) noexcept { return parse_name(kColorFormats, name, out); }

constexpr EnumName<DepthFormat> kDepthFormats[] = {
    {DepthFormat::float32, "float32"},       {DepthFormat::unorm16, "unorm16"},
    {DepthFormat::unorm24_s8, "unorm24_s8"}, {DepthFormat::s8_unorm24, "s8_unorm24"},
    {DepthFormat::rgba8_packed_linear, "rgba8_packed_linear"},
};
static_assert(sizeof kDepthFormats / sizeof kDepthFormats[0] == kDepthFormatCount, "every DepthFormat has a name");
const char* to_string(DepthFormat format) noexcept { return name_of(kDepthFormats, format); }
bool parse_depth_format(const char* name, DepthFormat* out) noexcept { return parse_name(kDepthFormats, name, out); }

constexpr EnumName<StatusCode> kStatusCodes[] = {
    {StatusCode::ok, "ok"},                         {StatusCode::null_pointer, "null_pointer"},
    {StatusCode::invalid_size, "invalid_size"},     {StatusCode::invalid_stride, "invalid_stride"},
    {StatusCode::size_mismatch, "size_mismatch"},   {StatusCode::aliasing, "aliasing"},
    {StatusCode::invalid_decoder, "invalid_decoder"}, {StatusCode::invalid_model, "invalid_model"},
    {StatusCode::invalid_option, "invalid_option"}, {StatusCode::cancelled, "cancelled"},
    {StatusCode::out_of_memory, "out_of_memory"},
};
const char* to_string(StatusCode code) noexcept { return name_of(kStatusCodes, code); }

constexpr EnumName<PickSource> kPickSources[] = {
    {PickSource::both, "both"}, {PickSource::left, "left"}, {PickSource::right, "right"}, {PickSource::none, "none"},
};
const char* to_string(PickSource source) noexcept { return name_of(kPickSources, source); }

}  // namespace reproject
