// The C interface's warp entry points, its last error's message and its names
// (src/c_api_internal.hpp).
#include "reproject/reproject.h"

#include <cstdint>
#include <cstring>

#include "src/c_api_internal.hpp"

namespace reproject {
namespace c_abi {
namespace {

// The message of the calling thread's last failure: kept here, so that reporting never allocates.
thread_local char last_message[192] = "ok";

}  // namespace

reproject_status report(const Status& status) noexcept {
  if (!status.ok()) {
    // Status keeps at most 191 characters: the copy never truncates.
    const char* message = status.message();
    std::size_t length = 0;
    while (length + 1 < sizeof(last_message) && message[length] != '\0') ++length;
    std::memcpy(last_message, message, length);
    last_message[length] = '\0';
  }
  return static_cast<reproject_status>(status.code());
}

namespace {

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

// The entry points of one eye, float-only or _buffers: the required arguments, then warp().
template <class Source, class Target>
reproject_status warp_one(const char* function, const Source* source, const reproject_decoder* decoder,
                          const reproject_parallax* model, const reproject_options* options, const Target* target,
                          const reproject_parallel_for* jobs) noexcept {
  if (source == nullptr || decoder == nullptr || model == nullptr || options == nullptr || target == nullptr) {
    const char* missing = source == nullptr    ? "source"
                          : decoder == nullptr ? "decoder"
                          : model == nullptr   ? "model"
                          : options == nullptr ? "options"
                                               : "target";
    return report(Status(StatusCode::null_pointer,
                         "%s: %s is null (source, decoder, model, options and target are required)", function,
                         missing));
  }
  return warp(buffers_of(*source), *decoder, *model, options, nullptr, buffers_of(*target), jobs);
}

// The entry points of both eyes from a centre view, float-only or _buffers.
template <class Source, class Target>
reproject_status warp_both(const char* function, const Source* centre, const reproject_decoder* decoder,
                           const reproject_parallax* centre_to_right, const reproject_options* options,
                           const Target* left, const Target* right, const reproject_parallel_for* jobs) noexcept {
  if (centre == nullptr || decoder == nullptr || centre_to_right == nullptr || options == nullptr || left == nullptr ||
      right == nullptr) {
    const char* missing = centre == nullptr            ? "centre"
                          : decoder == nullptr         ? "decoder"
                          : centre_to_right == nullptr ? "centre_to_right"
                          : options == nullptr         ? "options"
                          : left == nullptr            ? "left"
                                                       : "right";
    return report(Status(StatusCode::null_pointer,
                         "%s: %s is null (centre, decoder, model, options, left and right are required)", function,
                         missing));
  }
  const reproject_target_buffers& left_buffers = buffers_of(*left);
  return warp(buffers_of(*centre), *decoder, *centre_to_right, options, &left_buffers, buffers_of(*right), jobs);
}

// A C value as the name of the C++ enum E. The enums hold 0..255: a value beyond cannot be cast
// (256 would wrap onto 0's name), so it is "unknown" here; inside, to_string gives "unknown" for a
// value no enumerator has (src/names.hpp), so every name function answers alike.
template <class E>
const char* name_of(std::int32_t value) noexcept {
  return fits_enum(value) ? to_string(static_cast<E>(value)) : "unknown";
}

}  // namespace
}  // namespace c_abi
}  // namespace reproject

using namespace reproject;
using namespace reproject::c_abi;

extern "C" {

int32_t reproject_abi_version(void) { return REPROJECT_C_ABI_VERSION; }

const char* reproject_last_error_message(void) { return last_message; }

const char* reproject_status_name(reproject_status status) { return name_of<StatusCode>(status); }
const char* reproject_method_name(int32_t method) { return name_of<Method>(method); }
const char* reproject_arch_name(int32_t arch) { return name_of<Arch>(arch); }
const char* reproject_encoding_name(int32_t encoding) { return name_of<DepthEncoding>(encoding); }
const char* reproject_color_format_name(int32_t format) { return name_of<ColorFormat>(format); }
const char* reproject_depth_format_name(int32_t format) { return name_of<DepthFormat>(format); }

reproject_status reproject_warp(const reproject_source* source, const reproject_decoder* decoder,
                                const reproject_parallax* model, const reproject_options* options,
                                const reproject_target* target, const reproject_parallel_for* jobs) {
  return warp_one("reproject_warp", source, decoder, model, options, target, jobs);
}

reproject_status reproject_warp_pair(const reproject_source* centre, const reproject_decoder* decoder,
                                     const reproject_parallax* centre_to_right, const reproject_options* options,
                                     const reproject_target* left, const reproject_target* right,
                                     const reproject_parallel_for* jobs) {
  return warp_both("reproject_warp_pair", centre, decoder, centre_to_right, options, left, right, jobs);
}

reproject_status reproject_warp_buffers(const reproject_source_buffers* source, const reproject_decoder* decoder,
                                        const reproject_parallax* model, const reproject_options* options,
                                        const reproject_target_buffers* target, const reproject_parallel_for* jobs) {
  return warp_one("reproject_warp_buffers", source, decoder, model, options, target, jobs);
}

reproject_status reproject_warp_pair_buffers(const reproject_source_buffers* centre, const reproject_decoder* decoder,
                                             const reproject_parallax* centre_to_right,
                                             const reproject_options* options, const reproject_target_buffers* left,
                                             const reproject_target_buffers* right, const reproject_parallel_for* jobs) {
  return warp_both("reproject_warp_pair_buffers", centre, decoder, centre_to_right, options, left, right,
                   jobs);
}

}  // extern "C"
