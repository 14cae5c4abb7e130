// Internal: a call's plan and rows taken apart so that the rows can be split over threads
// (Options::threads, ParallelFor). make_frame() and run_rows() of frame.hpp are these pieces run
// in sequence on the calling thread. Not installed.
//
// Kept apart from frame.hpp, which the kernels include, so that the threading changes touch no
// kernel translation unit; folding these declarations into frame.hpp later changes nothing.
#pragma once

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {

// The plan without the near limit when near_pass_needed() (Options::max_negative_parallax unset,
// and a method that searches from the near end): then the caller reduces nearest_key_in_rows() over every row (with std::max, starting from key_far, rows in
// order) and passes the result to set_near_key(). With the option set the plan is complete.
Frame plan_frame(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target);

// Whether the plan still needs the frame's nearest key (nearest_key_in_rows, set_near_key).
bool near_pass_needed(const Frame& f);

// The fields that follow from the near end of the rays: p_near, the march step, the padding.
void set_near_key(Frame& f, float key_near);

// max(key_far, s * p) over the decoded parallax of rows [row_begin, row_end), in row order.
// Taken band by band and reduced in band order, this is bit for bit the whole frame's value
// (std::max keeps the first of equal values, so even the sign of a zero does not depend on
// where the bands split).
float nearest_key_in_rows(const Frame& f, const KernelTable& kernels, RowScratch& scratch, int row_begin,
                          int row_end);

// Sizes `scratch` for any frame with f's widths and guard, whatever its near limit (the padding
// is sized for the widest the plan allows), so that later calls with the same sizes never
// allocate, whatever their depth. Valid before set_near_key().
void prepare_scratch(const Frame& f, RowScratch& scratch);

// run_rows() with the caller's scratch (prepared for f).
void run_rows(const Frame& f, const KernelTable& kernels, RowScratch& scratch, int row_begin, int row_end);

// A pair's two eyes (reproject_pair: `left` is the mirror of `right`, same source and options),
// row by row: each source row is read from memory once and serves both eyes from the cache.
// Each eye's output is bit for bit that of run_rows() on its own frame.
void run_pair_rows(const Frame& left, const Frame& right, const KernelTable& kernels, RowScratch& scratch,
                   int row_begin, int row_end);

// Whether a pair's eyes are mirrored in the plan too: s flips from one eye to the other (b != 0).
// Then they have the same nearest key (eye k's key is s_k * p_k and both signs flip), so the
// right eye's near pass (nearest_key_in_rows) serves both, and the left eye's parallax row is the
// right eye's negated. With b = +-0 each eye does its own.
bool mirrored_eyes(const Frame& left, const Frame& right);

}  // namespace detail
}  // namespace reproject
