// The C interface (include/reproject/reproject.h): converts the plain C structs to the C++ views
// and calls the C++ API, so both compute the same thing bit for bit. Nothing here throws, and
// nothing allocates: the message of a failure is kept in a thread-local buffer.
#include "reproject/reproject.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "reproject/reproject.hpp"

namespace {

using namespace reproject;

// Values of the C constants are the C++ enumerators': checked here so that neither side drifts.
static_assert(REPROJECT_INVALID_OPTION == static_cast<int>(StatusCode::invalid_option), "status codes");
static_assert(REPROJECT_METHOD_EXACT == static_cast<int>(Method::exact), "methods");
static_assert(REPROJECT_ARCH_AVX512 == static_cast<int>(Arch::avx512), "arches");
static_assert(REPROJECT_PIXEL_CLIPPED == static_cast<int>(PixelStatus::clipped), "pixel statuses");
static_assert(REPROJECT_FILL_NONE == static_cast<int>(HoleFill::none), "hole fills");
static_assert(REPROJECT_EDGE_MIRROR == static_cast<int>(EdgeMode::mirror), "edge modes");
static_assert(REPROJECT_DEPTH_DISPARITY == static_cast<int>(DepthEncoding::disparity), "encodings");
static_assert(REPROJECT_CENTRE_TO_RIGHT == static_cast<int>(EyeDirection::centre_to_right), "directions");
static_assert(REPROJECT_LAYOUT_INTERLEAVED_RGBA == static_cast<int>(ColorLayout::interleaved_rgba), "layouts");

thread_local char last_message[192] = "ok";

// Records a failure's message for reproject_last_error_message() and returns its code.
reproject_status report(const Status& status) noexcept {
  if (!status.ok()) {
    std::strncpy(last_message, status.message(), sizeof(last_message) - 1);
    last_message[sizeof(last_message) - 1] = '\0';
  }
  return static_cast<reproject_status>(status.code());
}

FloatPlane view(const reproject_plane& p) noexcept { return FloatPlane{p.data, p.width, p.height, p.stride}; }
MutableFloatPlane view(const reproject_mut_plane& p) noexcept {
  return MutableFloatPlane{p.data, p.width, p.height, p.stride};
}
BytePlane view(const reproject_byte_plane& p) noexcept { return BytePlane{p.data, p.width, p.height, p.stride}; }

// The layout and channel count are passed through unchecked: the C++ validation reports them.
template <class CColor, class View>
View color_view(const CColor& c) noexcept {
  View v;
  v.layout = static_cast<ColorLayout>(c.layout);
  v.channels = c.channels;
  for (int i = 0; i < 4; ++i) v.plane[i] = view(c.plane[i]);
  return v;
}

SourceView view(const reproject_source& s) noexcept {
  SourceView v;
  v.color = color_view<reproject_color, ColorView>(s.color);
  v.depth = view(s.depth);
  return v;
}
TargetView view(const reproject_target& t) noexcept {
  TargetView v;
  v.color = color_view<reproject_mut_color, MutableColorView>(t.color);
  v.depth = view(t.depth);
  v.status = view(t.status);
  v.source_x = view(t.source_x);
  return v;
}

DepthDecoder decoder_of(const reproject_decoder& d) noexcept {
  switch (d.encoding) {
    case REPROJECT_DEPTH_LINEAR: return DepthDecoder::linear();
    case REPROJECT_DEPTH_DISPARITY: return DepthDecoder::disparity();
    default: return DepthDecoder::from_near_far(static_cast<DepthEncoding>(d.encoding), d.near_plane, d.far_plane);
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
  const Status status = d.validate();
  *out = c_decoder(d);
  if (!status.ok()) {
    out->encoding = encoding;
    out->near_plane = out->far_plane = std::numeric_limits<double>::quiet_NaN();
  }
  return report(status);
}

reproject_status model_out(const ParallaxModel& m, reproject_parallax* out) noexcept {
  if (out == nullptr) return report(Status(StatusCode::null_pointer, "parallax model output is null"));
  out->a = m.a;
  out->b = m.b;
  return report(m.validate());
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

}  // namespace

extern "C" {

int32_t reproject_abi_version(void) { return REPROJECT_C_ABI_VERSION; }

const char* reproject_last_error_message(void) { return last_message; }

const char* reproject_status_name(reproject_status status) {
  if (status < REPROJECT_OK || status > REPROJECT_INVALID_OPTION) return "?";
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
  const DepthDecoder d = DepthDecoder::from_near_far(static_cast<DepthEncoding>(encoding), near_plane, far_plane);
  // Keep what the caller passed, so that later uses rebuild (and refuse) the same decoder.
  *out = reproject_decoder{encoding, 0, near_plane, far_plane};
  return report(d.validate());
}
reproject_status reproject_decoder_linear(reproject_decoder* out) {
  return reproject_decoder_from_near_far(REPROJECT_DEPTH_LINEAR, 0.0, 0.0, out);
}
reproject_status reproject_decoder_disparity(reproject_decoder* out) {
  return reproject_decoder_from_near_far(REPROJECT_DEPTH_DISPARITY, 0.0, 0.0, out);
}
reproject_status reproject_decoder_from_d3d_projection(const float m[16], int32_t encoding, reproject_decoder* out) {
  return from_matrix(DepthDecoder::from_d3d_projection(m, static_cast<DepthEncoding>(encoding)), encoding, out);
}
reproject_status reproject_decoder_from_gl_projection(const float m[16], int32_t encoding, reproject_decoder* out) {
  return from_matrix(DepthDecoder::from_gl_projection(m, static_cast<DepthEncoding>(encoding)), encoding, out);
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
  return model_out(ParallaxModel::from_stereo(separation, convergence, width, static_cast<EyeDirection>(direction)), out);
}
reproject_status reproject_parallax_from_physical(double interocular, double screen_width, double convergence,
                                                  int32_t width, int32_t direction, reproject_parallax* out) {
  return model_out(ParallaxModel::from_physical(interocular, screen_width, convergence, width,
                                                static_cast<EyeDirection>(direction)),
                   out);
}
reproject_status reproject_parallax_from_disparity(int32_t direction, reproject_parallax* out) {
  return model_out(ParallaxModel::from_disparity(static_cast<EyeDirection>(direction)), out);
}

reproject_status reproject_warp(const reproject_source* source, const reproject_decoder* decoder,
                                const reproject_parallax* model, const reproject_options* options,
                                const reproject_target* target, const reproject_parallel_for* jobs) {
  if (source == nullptr || decoder == nullptr || model == nullptr || target == nullptr) {
    return report(Status(StatusCode::null_pointer, "reproject_warp: source, decoder, model and target are required"));
  }
  Options o;
  const Status parsed = options_of(options, &o);
  if (!parsed.ok()) return report(parsed);
  const ParallaxModel m{model->a, model->b};
  if (jobs != nullptr && jobs->run != nullptr) {
    const ParallelFor hook{const_cast<reproject_parallel_for*>(jobs), run_c_jobs};
    return report(reproject::reproject(view(*source), decoder_of(*decoder), m, o, view(*target), hook));
  }
  return report(reproject::reproject(view(*source), decoder_of(*decoder), m, o, view(*target)));
}

reproject_status reproject_warp_pair(const reproject_source* centre, const reproject_decoder* decoder,
                                     const reproject_parallax* centre_to_right, const reproject_options* options,
                                     const reproject_target* left, const reproject_target* right,
                                     const reproject_parallel_for* jobs) {
  if (centre == nullptr || decoder == nullptr || centre_to_right == nullptr || left == nullptr || right == nullptr) {
    return report(Status(StatusCode::null_pointer,
                         "reproject_warp_pair: centre, decoder, model, left and right are required"));
  }
  Options o;
  const Status parsed = options_of(options, &o);
  if (!parsed.ok()) return report(parsed);
  const ParallaxModel m{centre_to_right->a, centre_to_right->b};
  if (jobs != nullptr && jobs->run != nullptr) {
    const ParallelFor hook{const_cast<reproject_parallel_for*>(jobs), run_c_jobs};
    return report(reproject::reproject_pair(view(*centre), decoder_of(*decoder), m, o, view(*left), view(*right), hook));
  }
  return report(reproject::reproject_pair(view(*centre), decoder_of(*decoder), m, o, view(*left), view(*right)));
}

}  // extern "C"
