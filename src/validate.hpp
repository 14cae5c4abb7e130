// Internal: validation and view normalisation, once at a call's entry. Every check of
// docs/ERRORS.md runs here, in the order that page gives, before any pixel is touched; what
// passes comes out normalised, so that nothing downstream derives a view again.
#pragma once

#include "reproject/reproject.hpp"

namespace reproject {
namespace detail {

Status check_options(const Options& options);
Status check_jobs(const ParallelFor& jobs);

// A validated call's views. The source's depth is always a depth buffer (a float plane becomes
// float32 with its stride in bytes; `depth` is cleared); each target keeps only the outputs it
// asked for (the others are cleared: their fields were never checked), with its output depth,
// if any, as a depth buffer. This is the form kernels/frame.hpp's plan_frame() takes.
struct CallViews {
  SourceView source;
  TargetView targets[2];
  int target_count = 0;
  bool empty = false;  // a frame of width or height 0: valid, and nothing to do
};

// The decoder, the model, the options, the source, each target (named names[i] in messages) and
// the aliasing between them, in that order; on success *views holds the normalised views (only
// `empty` when the frame is empty). At most two targets.
Status check_call(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                  const Options& options, const TargetView* const* targets, const char* const* names, int target_count,
                  CallViews* views);

}  // namespace detail
}  // namespace reproject
