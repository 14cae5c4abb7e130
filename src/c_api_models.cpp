// The C interface's decoders, parallax models, options, cancel flag and instruction sets
// (src/c_api_internal.hpp).
#include "reproject/reproject.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>

#include "src/c_api_internal.hpp"

namespace reproject {
namespace c_abi {
namespace {

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

}  // namespace

Status check_encoding(int32_t encoding) noexcept {
  if (fits_enum(encoding)) return Status();
  return Status(StatusCode::invalid_decoder, "depth encoding %d is not a known encoding", static_cast<int>(encoding));
}

DepthDecoder decoder_of(const reproject_decoder& d) noexcept {
  switch (d.encoding) {
    case REPROJECT_DEPTH_LINEAR: return DepthDecoder::linear();
    case REPROJECT_DEPTH_DISPARITY: return DepthDecoder::disparity();
    default: return DepthDecoder::from_near_far(encoding_of(d.encoding), d.near_plane, d.far_plane);
  }
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

}  // namespace c_abi
}  // namespace reproject

using namespace reproject;
using namespace reproject::c_abi;

extern "C" {

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
reproject_status reproject_parallax_from_rig(double interaxial, double convergence, double horizontal_fov,
                                             int32_t width, int32_t direction, reproject_parallax* out) {
  return model_out(StereoCamera::from_rig(interaxial, convergence, horizontal_fov).parallax(width, direction_of(direction)),
                   direction, out);
}
reproject_status reproject_parallax_from_relative(double max_parallax, double zero_plane, int32_t width,
                                                  int32_t direction, reproject_parallax* out) {
  return model_out(ParallaxModel::from_relative(max_parallax, zero_plane, width, direction_of(direction)), direction,
                   out);
}
reproject_status reproject_parallax_from_disparity(int32_t direction, reproject_parallax* out) {
  return model_out(ParallaxModel::from_disparity(direction_of(direction)), direction, out);
}

}  // extern "C"
