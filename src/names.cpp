// Every public enum's names, in one table each (src/names.hpp), and the public to_string and
// parse_* functions over them.
#include "src/names.hpp"

#include "reproject/formats.hpp"
#include "reproject/reproject.hpp"
#include "reproject/stereo.hpp"

namespace reproject {
namespace {

using detail::EnumName;
using detail::name_of;
using detail::parse_name;

constexpr EnumName<Method> kMethods[] = {
    {Method::scanline, "scanline"}, {Method::march16, "march16"}, {Method::single, "single"},
    {Method::secant, "secant"},     {Method::exact, "exact"},
};
constexpr EnumName<Arch> kArches[] = {
    {Arch::scalar, "scalar"}, {Arch::sse, "sse"}, {Arch::avx2, "avx2"}, {Arch::avx512, "avx512"}, {Arch::neon, "neon"},
};
constexpr EnumName<HoleFill> kHoleFills[] = {
    {HoleFill::background, "background"}, {HoleFill::foreground, "foreground"}, {HoleFill::none, "none"},
};
constexpr EnumName<EdgeMode> kEdgeModes[] = {
    {EdgeMode::clamp, "clamp"}, {EdgeMode::none, "none"}, {EdgeMode::black, "black"}, {EdgeMode::mirror, "mirror"},
};
constexpr EnumName<DepthEncoding> kEncodings[] = {
    {DepthEncoding::linear, "linear"},
    {DepthEncoding::standard, "standard"},
    {DepthEncoding::gl_ndc, "gl_ndc"},
    {DepthEncoding::reversed, "reversed"},
    {DepthEncoding::reversed_infinite, "reversed_infinite"},
    {DepthEncoding::infinite, "infinite"},
    {DepthEncoding::disparity, "disparity"},
};
// Hyphens are the names; underscores are accepted too (the C++ spelling).
constexpr EnumName<EyeDirection> kDirections[] = {
    {EyeDirection::left_to_right, "left-to-right"},     {EyeDirection::right_to_left, "right-to-left"},
    {EyeDirection::centre_to_left, "centre-to-left"},   {EyeDirection::centre_to_right, "centre-to-right"},
    {EyeDirection::left_to_right, "left_to_right"},     {EyeDirection::right_to_left, "right_to_left"},
    {EyeDirection::centre_to_left, "centre_to_left"},   {EyeDirection::centre_to_right, "centre_to_right"},
};
constexpr EnumName<ColorFormat> kColorFormats[] = {
    {ColorFormat::float32, "float32"}, {ColorFormat::rgba8, "rgba8"}, {ColorFormat::rgba8_srgb, "rgba8_srgb"},
    {ColorFormat::rgba16f, "rgba16f"},
};
constexpr EnumName<DepthFormat> kDepthFormats[] = {
    {DepthFormat::float32, "float32"},       {DepthFormat::unorm16, "unorm16"},
    {DepthFormat::unorm24_s8, "unorm24_s8"}, {DepthFormat::s8_unorm24, "s8_unorm24"},
    {DepthFormat::rgba8_packed_linear, "rgba8_packed_linear"},
};
constexpr EnumName<StatusCode> kStatusCodes[] = {
    {StatusCode::ok, "ok"},
    {StatusCode::null_pointer, "null_pointer"},
    {StatusCode::invalid_size, "invalid_size"},
    {StatusCode::invalid_stride, "invalid_stride"},
    {StatusCode::size_mismatch, "size_mismatch"},
    {StatusCode::aliasing, "aliasing"},
    {StatusCode::invalid_decoder, "invalid_decoder"},
    {StatusCode::invalid_model, "invalid_model"},
    {StatusCode::invalid_option, "invalid_option"},
    {StatusCode::cancelled, "cancelled"},
};
constexpr EnumName<PickSource> kPickSources[] = {
    {PickSource::both, "both"}, {PickSource::left, "left"}, {PickSource::right, "right"}, {PickSource::none, "none"},
};

// Every value has a name: the count constants of the headers match the tables.
static_assert(sizeof kMethods / sizeof kMethods[0] == kMethodCount, "method names");
static_assert(sizeof kArches / sizeof kArches[0] == kArchCount, "arch names");
static_assert(sizeof kHoleFills / sizeof kHoleFills[0] == kHoleFillCount, "hole fill names");
static_assert(sizeof kEdgeModes / sizeof kEdgeModes[0] == kEdgeModeCount, "edge mode names");
static_assert(sizeof kEncodings / sizeof kEncodings[0] == kDepthEncodingCount, "encoding names");
static_assert(sizeof kDirections / sizeof kDirections[0] == 2 * kEyeDirectionCount, "direction names");
static_assert(sizeof kColorFormats / sizeof kColorFormats[0] == kColorFormatCount, "colour format names");
static_assert(sizeof kDepthFormats / sizeof kDepthFormats[0] == kDepthFormatCount, "depth format names");

}  // namespace

const char* to_string(Method method) noexcept { return name_of(kMethods, method); }
bool parse_method(const char* name, Method* out) noexcept { return parse_name(kMethods, name, out); }
const char* to_string(Arch arch) noexcept { return name_of(kArches, arch); }
bool parse_arch(const char* name, Arch* out) noexcept { return parse_name(kArches, name, out); }
const char* to_string(HoleFill fill) noexcept { return name_of(kHoleFills, fill); }
bool parse_hole_fill(const char* name, HoleFill* out) noexcept { return parse_name(kHoleFills, name, out); }
const char* to_string(EdgeMode edge) noexcept { return name_of(kEdgeModes, edge); }
bool parse_edge_mode(const char* name, EdgeMode* out) noexcept { return parse_name(kEdgeModes, name, out); }
const char* to_string(DepthEncoding encoding) noexcept { return name_of(kEncodings, encoding); }
bool parse_encoding(const char* name, DepthEncoding* out) noexcept { return parse_name(kEncodings, name, out); }
const char* to_string(EyeDirection direction) noexcept { return name_of(kDirections, direction); }
bool parse_direction(const char* name, EyeDirection* out) noexcept { return parse_name(kDirections, name, out); }
const char* to_string(ColorFormat format) noexcept { return name_of(kColorFormats, format); }
bool parse_color_format(const char* name, ColorFormat* out) noexcept { return parse_name(kColorFormats, name, out); }
const char* to_string(DepthFormat format) noexcept { return name_of(kDepthFormats, format); }
bool parse_depth_format(const char* name, DepthFormat* out) noexcept { return parse_name(kDepthFormats, name, out); }
const char* to_string(StatusCode code) noexcept { return name_of(kStatusCodes, code); }
const char* to_string(PickSource source) noexcept { return name_of(kPickSources, source); }

}  // namespace reproject
