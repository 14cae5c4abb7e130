// The C interface (include/reproject/reproject.h): converts the plain C structs to the C++ views
// and calls the C++ API, so both compute the same thing bit for bit. Nothing here throws, and
// nothing allocates: the message of a failure is kept in a thread-local buffer.
#include "reproject/reproject.h"

#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>

#include "reproject/reproject.hpp"

namespace {

using namespace reproject;

// Values of the C constants are the C++ enumerators': checked here so that neither side drifts.
static_assert(REPROJECT_INVALID_OPTION == static_cast<int>(StatusCode::invalid_option) &&
                  REPROJECT_CANCELLED == static_cast<int>(StatusCode::cancelled),
              "status codes");
static_assert(REPROJECT_METHOD_EXACT == static_cast<int>(Method::exact), "methods");
static_assert(REPROJECT_ARCH_AVX512 == static_cast<int>(Arch::avx512) && REPROJECT_ARCH_NEON == static_cast<int>(Arch::neon) &&
                  kArchCount == 5, "arches");
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

// reproject_cancel's storage holds the C++ flag (Options::cancel), made by reproject_cancel_init;
// lock-free, so that a signal handler may set it.
static_assert(sizeof(std::atomic<bool>) <= sizeof(reproject_cancel) && alignof(std::atomic<bool>) <= alignof(reproject_cancel),
              "reproject_cancel holds a std::atomic<bool>");
static_assert(std::atomic<bool>::is_always_lock_free, "the cancel flag is set from signal handlers");
std::atomic<bool>* flag_of(reproject_cancel* cancel) noexcept {
  return std::launder(reinterpret_cast<std::atomic<bool>*>(cancel));
}
const std::atomic<bool>* flag_of(const reproject_cancel* cancel) noexcept {
  return std::launder(reinterpret_cast<const std::atomic<bool>*>(cancel));
}

thread_local char last_message[192] = "ok";

// Records a failure's message for reproject_last_error_message() and returns its code.
reproject_status report(const Status& status) noexcept {
  if (!status.ok()) {
    std::strncpy(last_message, status.message(), sizeof(last_message) - 1);
    last_message[sizeof(last_message) - 1] = '\0';
  }
  return static_cast<reproject_status>(status.code());
}

// The C strides are int64_t; where ptrdiff_t is narrower (32-bit targets) a stride beyond it
// becomes PTRDIFF_MIN, which the validation refuses as shorter than the row, instead of being
// truncated to a plausible wrong pitch.
std::ptrdiff_t stride_of(std::int64_t stride) noexcept {
  if constexpr (sizeof(std::ptrdiff_t) < sizeof(std::int64_t)) {
    if (stride > PTRDIFF_MAX || stride < PTRDIFF_MIN) return PTRDIFF_MIN;
  }
  return static_cast<std::ptrdiff_t>(stride);
}

FloatPlane view(const reproject_plane& p) noexcept { return FloatPlane{p.data, p.width, p.height, stride_of(p.stride)}; }
MutableFloatPlane view(const reproject_mut_plane& p) noexcept {
  return MutableFloatPlane{p.data, p.width, p.height, stride_of(p.stride)};
}
BytePlane view(const reproject_byte_plane& p) noexcept {
  return BytePlane{p.data, p.width, p.height, stride_of(p.stride)};
}

// The C structs to the C++ views: one function per struct, shared by the float-only calls (whose
// structs are lifted into the _buffers ones) and the _buffers calls. Values that C++ keeps in 8-bit
// enums (layout, formats) are range-checked before the cast, as a cast of an unknown value could
// wrap onto a known one; sizes, strides, channel counts and the rest are the C++ validation's.
template <class CColor, class CPixels, class View>
Status color_of(const CColor& c, const CPixels& p, const char* name, View* out) noexcept {
  if (c.layout != REPROJECT_LAYOUT_PLANAR && c.layout != REPROJECT_LAYOUT_INTERLEAVED_RGBA)
    return Status(StatusCode::invalid_option, "%s color.layout %d is not a known layout (REPROJECT_LAYOUT_*)", name,
                  static_cast<int>(c.layout));
  if (p.format < 0 || p.format >= kColorFormatCount)
    return Status(StatusCode::invalid_option, "%s pixels.format %d is not a known colour format (REPROJECT_COLOR_*)",
                  name, static_cast<int>(p.format));
  if (p.reserved != 0)  // kept 0 now, so that a later version may give it a meaning
    return Status(StatusCode::invalid_option, "%s pixels.reserved is %d; it must be 0", name, static_cast<int>(p.reserved));
  View v;
  if (p.format == REPROJECT_COLOR_FLOAT32) {
    if (p.data != nullptr)
      return Status(StatusCode::invalid_option, "%s pixels.data is set but pixels.format is float32: float colour "
                    "goes in color, packed pixels need their REPROJECT_COLOR_* format", name);
    v.layout = static_cast<ColorLayout>(c.layout);
    v.channels = c.channels;
    for (int i = 0; i < 4; ++i) v.plane[i] = view(c.plane[i]);
  } else {
    bool planes = c.channels != 0;
    for (int i = 0; i < 4; ++i) planes = planes || c.plane[i].data != nullptr;
    if (planes)
      return Status(StatusCode::invalid_option, "%s: both color (float planes) and pixels (%s) are set; set one", name,
                    to_string(static_cast<ColorFormat>(p.format)));
    v = View::packed(static_cast<ColorFormat>(p.format), p.data, p.width, p.height, stride_of(p.stride));
  }
  *out = v;
  return Status();
}

template <class CBuffer, class Buffer>
Status depth_buffer_of(const CBuffer& d, const char* name, Buffer* out) noexcept {
  if (d.format < 0 || d.format >= kDepthFormatCount)
    return Status(StatusCode::invalid_option,
                  "%s depth_buffer.format %d is not a known depth format (REPROJECT_DEPTH_FORMAT_*)", name,
                  static_cast<int>(d.format));
  if (d.reserved != 0)
    return Status(StatusCode::invalid_option, "%s depth_buffer.reserved is %d; it must be 0", name,
                  static_cast<int>(d.reserved));
  Buffer b = Buffer::of(static_cast<DepthFormat>(d.format), d.data, d.width, d.height, stride_of(d.stride));
  b.linear_near = d.linear_near;
  b.linear_far = d.linear_far;
  *out = b;
  return Status();
}

// Both depths are passed on as given: the C++ validation refuses a view with both set.
Status source_of(const reproject_source_buffers& s, const char* name, SourceView* out) noexcept {
  SourceView v;
  Status status = color_of(s.color, s.pixels, name, &v.color);
  if (status.ok()) status = depth_buffer_of(s.depth_buffer, name, &v.depth_buffer);
  v.depth = view(s.depth);
  *out = v;
  return status;
}
Status target_of(const reproject_target_buffers& t, const char* name, TargetView* out) noexcept {
  TargetView v;
  Status status = color_of(t.color, t.pixels, name, &v.color);
  if (status.ok()) status = depth_buffer_of(t.depth_buffer, name, &v.depth_buffer);
  v.depth = view(t.depth);
  v.status = view(t.status);
  v.source_x = view(t.source_x);
  *out = v;
  return status;
}

// The float-only structs are the _buffers ones with no pixels and no depth buffer.
reproject_source_buffers buffers_of(const reproject_source& s) noexcept {
  reproject_source_buffers b{};
  b.color = s.color;
  b.depth = s.depth;
  return b;
}
reproject_target_buffers buffers_of(const reproject_target& t) noexcept {
  reproject_target_buffers b{};
  b.color = t.color;
  b.depth = t.depth;
  b.status = t.status;
  b.source_x = t.source_x;
  return b;
}

// C's int32 values as the C++ enums, whose underlying type is uint8_t: a value beyond it must not
// wrap onto a valid one (257 would become 1, "standard"). Unknown values inside 0..255 are refused
// by the C++ side; those beyond are refused here, naming the value the caller passed.
bool fits_enum(int32_t value) noexcept { return value >= 0 && value <= 255; }

Status check_encoding(int32_t encoding) noexcept {
  if (fits_enum(encoding)) return Status();
  return Status(StatusCode::invalid_decoder, "depth encoding %d is not a known encoding", static_cast<int>(encoding));
}

Status check_direction(int32_t direction) noexcept {
  if (fits_enum(direction)) return Status();
  return Status(StatusCode::invalid_model, "eye direction %d is not a known direction", static_cast<int>(direction));
}

// An encoding beyond the enum becomes 255, which no encoding has: an invalid decoder (NaN planes).
DepthEncoding encoding_of(int32_t encoding) noexcept {
  return static_cast<DepthEncoding>(fits_enum(encoding) ? encoding : 255);
}
EyeDirection direction_of(int32_t direction) noexcept {
  return static_cast<EyeDirection>(fits_enum(direction) ? direction : 255);
}

DepthDecoder decoder_of(const reproject_decoder& d) noexcept {
  switch (d.encoding) {
    case REPROJECT_DEPTH_LINEAR: return DepthDecoder::linear();
    case REPROJECT_DEPTH_DISPARITY: return DepthDecoder::disparity();
    default: return DepthDecoder::from_near_far(encoding_of(d.encoding), d.near_plane, d.far_plane);
  }
}

reproject_decoder c_decoder(const DepthDecoder& d) noexcept {
  reproject_decoder out{};
  out.encoding = static_cast<int32_t>(d.encoding());
  out.near_plane = d.near_plane();
  out.far_plane = d.far_plane();
  return out;
}

// A matrix the decoder cannot read leaves no planes to rebuild it from: NaN planes make every later
// use of *out fail validation (the factory itself returns the matrix's own message).
reproject_status from_matrix(const DepthDecoder& d, int32_t encoding, reproject_decoder* out) noexcept {
  if (out == nullptr) return report(Status(StatusCode::null_pointer, "decoder output is null"));
  const Status range = check_encoding(encoding);
  const Status status = range.ok() ? d.validate() : range;
  *out = c_decoder(d);
  if (!status.ok()) {
    out->encoding = encoding;
    out->near_plane = out->far_plane = std::numeric_limits<double>::quiet_NaN();
  }
  return report(status);
}

reproject_status model_out(const ParallaxModel& m, int32_t direction, reproject_parallax* out) noexcept {
  if (out == nullptr) return report(Status(StatusCode::null_pointer, "parallax model output is null"));
  out->a = m.a;
  out->b = m.b;
  const Status range = check_direction(direction);
  return report(range.ok() ? m.validate() : range);
}

// Copies the fields the caller's struct holds (struct_size) over the defaults.
Status options_of(const reproject_options* c, Options* out) noexcept {
  reproject_options full;
  reproject_options_init(&full);
  if (c != nullptr) {
    if (c->struct_size < sizeof(std::uint32_t)) {
      return Status(StatusCode::invalid_option, "options.struct_size %u is too small: use reproject_options_init",
                    static_cast<unsigned>(c->struct_size));
    }
    std::memcpy(&full, c, c->struct_size < sizeof(full) ? c->struct_size : sizeof(full));
    // A struct from an older header ends before `cancel`, or inside it: not a pointer.
    if (c->struct_size < offsetof(reproject_options, cancel) + sizeof(full.cancel)) full.cancel = nullptr;
  }
  Options o;
  o.method = static_cast<Method>(full.method);
  if (full.method < 0 || full.method >= kMethodCount) {
    return Status(StatusCode::invalid_option, "options.method %d is not a known method", static_cast<int>(full.method));
  }
  if (full.hole_fill < 0 || full.hole_fill > REPROJECT_FILL_NONE) {
    return Status(StatusCode::invalid_option, "options.hole_fill %d is not a known fill", static_cast<int>(full.hole_fill));
  }
  if (full.edge < 0 || full.edge > REPROJECT_EDGE_MIRROR) {
    return Status(StatusCode::invalid_option, "options.edge %d is not a known edge mode", static_cast<int>(full.edge));
  }
  if (full.arch < REPROJECT_ARCH_AUTO || full.arch >= kArchCount) {
    return Status(StatusCode::invalid_option, "options.arch %d is not a known instruction set", static_cast<int>(full.arch));
  }
  if (full.has_max_negative_parallax) o.max_negative_parallax = full.max_negative_parallax;
  o.hole_threshold = full.hole_threshold;
  o.hole_fill = static_cast<HoleFill>(full.hole_fill);
  o.edge = static_cast<EdgeMode>(full.edge);
  o.guard = full.guard;
  if (full.has_probe_parallax) o.probe_parallax = full.probe_parallax;
  o.march_steps = full.march_steps;
  o.secant_max_steps = full.secant_max_steps;
  if (full.arch != REPROJECT_ARCH_AUTO) o.arch = static_cast<Arch>(full.arch);
  o.threads = full.threads;
  o.cancel = full.cancel != nullptr ? flag_of(full.cancel) : nullptr;
  *out = o;
  return Status();
}

// The C job system behind the C++ ParallelFor: the two signatures differ only in int vs int32_t.
struct CJobs {
  const reproject_parallel_for* c;
  void (*task)(void*, int);
  void* task_context;
};
void c_task(void* context, int32_t index) {
  const CJobs* jobs = static_cast<const CJobs*>(context);
  jobs->task(jobs->task_context, index);
}
void run_c_jobs(void* context, int count, void (*task)(void*, int), void* task_context) {
  CJobs call{static_cast<const reproject_parallel_for*>(context), task, task_context};
  call.c->run(call.c->context, count, c_task, &call);
}

// Every reprojection entry point ends here: the options, the views, the decoder, the model and the
// job hook are handled once. `left` null: one eye (reproject), else both (reproject_pair).
reproject_status warp(const reproject_source_buffers& source, const reproject_decoder& decoder,
                      const reproject_parallax& model, const reproject_options* options,
                      const reproject_target_buffers* left, const reproject_target_buffers& right,
                      const reproject_parallel_for* jobs) noexcept {
  Options o;
  SourceView s;
  TargetView l, r;
  Status status = options_of(options, &o);
  if (status.ok()) status = source_of(source, left ? "centre" : "source", &s);
  if (status.ok() && left) status = target_of(*left, "left", &l);
  if (status.ok()) status = target_of(right, left ? "right" : "target", &r);
  if (status.ok()) status = check_encoding(decoder.encoding);
  if (status.ok() && jobs != nullptr && jobs->run == nullptr)
    status = Status(StatusCode::invalid_option, "jobs: run is null (pass jobs NULL for the library's own threads)");
  if (!status.ok()) return report(status);
  const DepthDecoder d = decoder_of(decoder);
  const ParallaxModel m{model.a, model.b};
  if (jobs != nullptr) {
    const ParallelFor hook{const_cast<reproject_parallel_for*>(jobs), run_c_jobs};
    return report(left ? reproject_pair(s, d, m, o, l, r, hook) : reproject::reproject(s, d, m, o, r, hook));
  }
  return report(left ? reproject_pair(s, d, m, o, l, r) : reproject::reproject(s, d, m, o, r));
}

// The first null argument of an entry point, by its name in reproject.h.
const char* null_name(const void* source, const void* decoder, const void* model, const void* options,
                      const void* target) noexcept {
  if (source == nullptr) return "source";
  if (decoder == nullptr) return "decoder";
  if (model == nullptr) return "model";
  if (options == nullptr) return "options";
  return target == nullptr ? "target" : "no argument";
}
const char* null_name(const void* centre, const void* decoder, const void* model, const void* options,
                      const void* left, const void* right) noexcept {
  if (centre == nullptr) return "centre";
  if (decoder == nullptr) return "decoder";
  if (model == nullptr) return "centre_to_right";
  if (options == nullptr) return "options";
  return left == nullptr ? "left" : right == nullptr ? "right" : "no argument";
}

}  // namespace

extern "C" {

int32_t reproject_abi_version(void) { return REPROJECT_C_ABI_VERSION; }

const char* reproject_last_error_message(void) { return last_message; }

const char* reproject_status_name(reproject_status status) {
  if (status < REPROJECT_OK || status > REPROJECT_CANCELLED) return "?";
  return to_string(static_cast<StatusCode>(status));
}
const char* reproject_method_name(int32_t method) {
  return method >= 0 && method < kMethodCount ? to_string(static_cast<Method>(method)) : "?";
}
const char* reproject_arch_name(int32_t arch) {
  return arch >= 0 && arch < kArchCount ? to_string(static_cast<Arch>(arch)) : "?";
}
const char* reproject_encoding_name(int32_t encoding) {
  return encoding >= 0 && encoding <= REPROJECT_DEPTH_DISPARITY ? to_string(static_cast<DepthEncoding>(encoding)) : "?";
}
const char* reproject_color_format_name(int32_t format) {
  return format >= 0 && format < kColorFormatCount ? to_string(static_cast<ColorFormat>(format)) : "?";
}
const char* reproject_depth_format_name(int32_t format) {
  return format >= 0 && format < kDepthFormatCount ? to_string(static_cast<DepthFormat>(format)) : "?";
}

void reproject_cancel_init(reproject_cancel* cancel) {
  if (cancel != nullptr) new (cancel) std::atomic<bool>(false);
}
void reproject_cancel_request(reproject_cancel* cancel) {
  if (cancel != nullptr) flag_of(cancel)->store(true, std::memory_order_relaxed);
}
int32_t reproject_cancel_requested(const reproject_cancel* cancel) {
  return cancel != nullptr && flag_of(cancel)->load(std::memory_order_relaxed) ? 1 : 0;
}

int32_t reproject_arch_supported(int32_t arch) {
  return arch >= 0 && arch < kArchCount && arch_supported(static_cast<Arch>(arch)) ? 1 : 0;
}
int32_t reproject_selected_arch(void) { return static_cast<int32_t>(selected_arch()); }

void reproject_options_init(reproject_options* options) {
  if (options == nullptr) return;
  const Options defaults;
  *options = reproject_options{};
  options->struct_size = sizeof(reproject_options);
  options->method = static_cast<int32_t>(defaults.method);
  options->hole_threshold = defaults.hole_threshold;
  options->hole_fill = static_cast<int32_t>(defaults.hole_fill);
  options->edge = static_cast<int32_t>(defaults.edge);
  options->guard = defaults.guard;
  options->march_steps = defaults.march_steps;
  options->secant_max_steps = defaults.secant_max_steps;
  options->arch = REPROJECT_ARCH_AUTO;
  options->threads = defaults.threads;
}

reproject_status reproject_decoder_from_near_far(int32_t encoding, double near_plane, double far_plane,
                                                 reproject_decoder* out) {
  if (out == nullptr) return report(Status(StatusCode::null_pointer, "decoder output is null"));
  const DepthDecoder d = DepthDecoder::from_near_far(encoding_of(encoding), near_plane, far_plane);
  // Keep what the caller passed, so that later uses rebuild (and refuse) the same decoder.
  *out = reproject_decoder{encoding, 0, near_plane, far_plane};
  const Status range = check_encoding(encoding);
  return report(range.ok() ? d.validate() : range);
}
reproject_status reproject_decoder_linear(reproject_decoder* out) {
  return reproject_decoder_from_near_far(REPROJECT_DEPTH_LINEAR, 0.0, 0.0, out);
}
reproject_status reproject_decoder_disparity(reproject_decoder* out) {
  return reproject_decoder_from_near_far(REPROJECT_DEPTH_DISPARITY, 0.0, 0.0, out);
}
reproject_status reproject_decoder_from_d3d_projection(const float m[16], int32_t encoding, reproject_decoder* out) {
  return from_matrix(DepthDecoder::from_d3d_projection(m, encoding_of(encoding)), encoding, out);
}
reproject_status reproject_decoder_from_gl_projection(const float m[16], int32_t encoding, reproject_decoder* out) {
  return from_matrix(DepthDecoder::from_gl_projection(m, encoding_of(encoding)), encoding, out);
}
float reproject_decoder_inverse_depth(const reproject_decoder* decoder, float stored) {
  if (decoder == nullptr) return std::numeric_limits<float>::quiet_NaN();
  return decoder_of(*decoder).inverse_depth(stored);
}
float reproject_decoder_linear_depth(const reproject_decoder* decoder, float stored) {
  if (decoder == nullptr) return std::numeric_limits<float>::quiet_NaN();
  return decoder_of(*decoder).linear_depth(stored);
}

reproject_status reproject_parallax_from_stereo(double separation, double convergence, int32_t width,
                                                int32_t direction, reproject_parallax* out) {
  return model_out(ParallaxModel::from_stereo(separation, convergence, width, direction_of(direction)), direction, out);
}
reproject_status reproject_parallax_from_physical(double interocular, double screen_width, double convergence,
                                                  int32_t width, int32_t direction, reproject_parallax* out) {
  return model_out(ParallaxModel::from_physical(interocular, screen_width, convergence, width, direction_of(direction)),
                   direction, out);
}
reproject_status reproject_parallax_from_disparity(int32_t direction, reproject_parallax* out) {
  return model_out(ParallaxModel::from_disparity(direction_of(direction)), direction, out);
}

reproject_status reproject_warp(const reproject_source* source, const reproject_decoder* decoder,
                                const reproject_parallax* model, const reproject_options* options,
                                const reproject_target* target, const reproject_parallel_for* jobs) {
  if (source == nullptr || decoder == nullptr || model == nullptr || options == nullptr || target == nullptr) {
    return report(Status(StatusCode::null_pointer, "reproject_warp: %s is null (source, decoder, model, options and "
                         "target are required)", null_name(source, decoder, model, options, target)));
  }
  return warp(buffers_of(*source), *decoder, *model, options, nullptr, buffers_of(*target), jobs);
}

reproject_status reproject_warp_pair(const reproject_source* centre, const reproject_decoder* decoder,
                                     const reproject_parallax* centre_to_right, const reproject_options* options,
                                     const reproject_target* left, const reproject_target* right,
                                     const reproject_parallel_for* jobs) {
  if (centre == nullptr || decoder == nullptr || centre_to_right == nullptr || options == nullptr || left == nullptr ||
      right == nullptr) {
    return report(Status(StatusCode::null_pointer, "reproject_warp_pair: %s is null (centre, decoder, model, options, "
                         "left and right are required)", null_name(centre, decoder, centre_to_right, options, left, right)));
  }
  const reproject_target_buffers left_buffers = buffers_of(*left);
  return warp(buffers_of(*centre), *decoder, *centre_to_right, options, &left_buffers, buffers_of(*right), jobs);
}

reproject_status reproject_warp_buffers(const reproject_source_buffers* source, const reproject_decoder* decoder,
                                        const reproject_parallax* model, const reproject_options* options,
                                        const reproject_target_buffers* target, const reproject_parallel_for* jobs) {
  if (source == nullptr || decoder == nullptr || model == nullptr || options == nullptr || target == nullptr) {
    return report(Status(StatusCode::null_pointer, "reproject_warp_buffers: %s is null (source, decoder, model, "
                         "options and target are required)", null_name(source, decoder, model, options, target)));
  }
  return warp(*source, *decoder, *model, options, nullptr, *target, jobs);
}

reproject_status reproject_warp_pair_buffers(const reproject_source_buffers* centre, const reproject_decoder* decoder,
                                             const reproject_parallax* centre_to_right,
                                             const reproject_options* options, const reproject_target_buffers* left,
                                             const reproject_target_buffers* right, const reproject_parallel_for* jobs) {
  if (centre == nullptr || decoder == nullptr || centre_to_right == nullptr || options == nullptr || left == nullptr ||
      right == nullptr) {
    return report(Status(StatusCode::null_pointer, "reproject_warp_pair_buffers: %s is null (centre, decoder, model, "
                         "options, left and right are required)",
                         null_name(centre, decoder, centre_to_right, options, left, right)));
  }
  return warp(*centre, *decoder, *centre_to_right, options, left, *right, jobs);
}

}  // extern "C"
