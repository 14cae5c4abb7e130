// Internal: the row driver. A call's rows, or a band of them on one thread (src/ splits a frame
// into bands over threads): each row is decoded, searched by the frame's method and resolved
// with one instruction set's kernels. Not installed.
#pragma once

#include "kernels/kernel_table.hpp"

namespace reproject::detail {

// max(key_far, s * p) over the decoded parallax of rows [row_begin, row_end), in row order.
// Taken band by band and reduced in band order, this is bit for bit the whole frame's value
// (std::max keeps the first of equal values, so even the sign of a zero does not depend on
// where the bands split).
float nearest_key_in_rows(const Frame& f, const KernelTable& kernels, int row_begin, int row_end);

// Rows [row_begin, row_end) of f with the caller's scratch (prepare_scratch'ed for f).
void run_rows(const Frame& f, const KernelTable& kernels, RowScratch& scratch, int row_begin, int row_end);

// A pair's two eyes (reproject_pair: `left` is the mirror of `right`, same source and options),
// row by row: each source row is read from memory once and serves both eyes from the cache.
// Each eye's output is bit for bit that of run_rows() on its own frame.
void run_pair_rows(const Frame& left, const Frame& right, const KernelTable& kernels, RowScratch& scratch,
                   int row_begin, int row_end);

}  // namespace reproject::detail
