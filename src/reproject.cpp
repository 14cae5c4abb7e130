// The entry points (include/reproject/reproject.hpp): validate and normalise the views once
// (src/validate.hpp), plan each eye (kernels/frame.hpp), then run the rows over threads
// (src/bands.hpp). Nothing is checked inside the pixel loops.
#include "reproject/reproject.hpp"

#include "kernels/color_formats.hpp"
#include "kernels/dispatch.hpp"
#include "kernels/frame.hpp"
#include "src/bands.hpp"
#include "src/memory.hpp"
#include "src/reproject_internal.hpp"
#include "src/validate.hpp"

namespace reproject {
namespace {

using detail::CallViews;
using detail::check_call;
using detail::check_jobs;
using detail::check_options;
using detail::Frame;
using detail::KernelTable;
using detail::plan_frame;
using detail::run_frames;

// Options::arch was checked by check_options.
const KernelTable& kernels_for(const Options& options) {
  return *detail::compiled_kernels(options.arch ? *options.arch : selected_arch());
}

// The sRGB lookup of an rgba8_srgb frame (kernels/color_formats.hpp SrgbLookup): `forced`, or the
// table's choice (gathers on a table with one way, after REPROJECT_SRGB_LOOKUP has been read, so
// that an unknown value is said on every set). Only tables that have both read it.
void choose_srgb_lookup(const KernelTable& kernels, Frame& frame, const detail::SrgbLookup* forced = nullptr) {
  if (frame.color_format != ColorFormat::rgba8_srgb) return;
  frame.srgb_lookup = forced ? *forced : detail::srgb_lookup_for(kernels);
}

Status reproject_one(const KernelTable& kernels, const SourceView& source, const DepthDecoder& decoder,
                     const ParallaxModel& model, const Options& options, const TargetView& target,
                     const ParallelFor* jobs, const detail::SrgbLookup* srgb_lookup = nullptr) {
  const detail::CallScope scope;
  const TargetView* targets[1] = {&target};
  const char* names[1] = {"target"};
  CallViews views;
  const Status status = check_call(source, decoder, model, options, targets, names, 1, &views);
  if (!status.ok() || views.empty) return status;
  Frame frame = plan_frame(views.source, decoder, model, options, views.targets[0]);
  choose_srgb_lookup(kernels, frame, srgb_lookup);
  return run_frames(kernels, &frame, 1, options, jobs);
}

// The pair: the left eye's model is the right eye's mirror (-a, -b), and both eyes' rows run
// together, row by row (kernels/rows.hpp run_pair_rows).
Status reproject_two(const SourceView& centre, const DepthDecoder& decoder, const ParallaxModel& centre_to_right,
                     const Options& options, const TargetView& left, const TargetView& right,
                     const ParallelFor* jobs) {
  const detail::CallScope scope;
  const ParallaxModel centre_to_left{-centre_to_right.a, -centre_to_right.b};
  const TargetView* targets[2] = {&left, &right};
  const char* names[2] = {"left", "right"};
  CallViews views;
  const Status status = check_call(centre, decoder, centre_to_right, options, targets, names, 2, &views);
  if (!status.ok() || views.empty) return status;
  Frame frames[2] = {plan_frame(views.source, decoder, centre_to_left, options, views.targets[0]),
                     plan_frame(views.source, decoder, centre_to_right, options, views.targets[1])};
  const KernelTable& kernels = kernels_for(options);
  for (Frame& frame : frames) choose_srgb_lookup(kernels, frame);
  return run_frames(kernels, frames, 2, options, jobs);
}

}  // namespace

namespace detail {

Status reproject_with(const KernelTable& kernels, const SourceView& source, const DepthDecoder& decoder,
                      const ParallaxModel& model, const Options& options, const TargetView& target,
                      const SrgbLookup* srgb_lookup) {
  return reproject_one(kernels, source, decoder, model, options, target, nullptr, srgb_lookup);
}

}  // namespace detail

Status reproject(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target) noexcept {
  if (Status status = check_options(options); !status.ok()) return status;
  return reproject_one(kernels_for(options), source, decoder, model, options, target, nullptr);
}

Status reproject(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target, const ParallelFor& jobs) noexcept {
  if (Status status = check_jobs(jobs); !status.ok()) return status;
  if (Status status = check_options(options); !status.ok()) return status;
  return reproject_one(kernels_for(options), source, decoder, model, options, target, &jobs);
}

Status reproject_pair(const SourceView& centre, const DepthDecoder& decoder, const ParallaxModel& centre_to_right,
                      const Options& options, const TargetView& left, const TargetView& right) noexcept {
  return reproject_two(centre, decoder, centre_to_right, options, left, right, nullptr);
}

Status reproject_pair(const SourceView& centre, const DepthDecoder& decoder, const ParallaxModel& centre_to_right,
                      const Options& options, const TargetView& left, const TargetView& right,
                      const ParallelFor& jobs) noexcept {
  if (Status status = check_jobs(jobs); !status.ok()) return status;
  return reproject_two(centre, decoder, centre_to_right, options, left, right, &jobs);
}

}  // namespace reproject
