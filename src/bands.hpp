// Internal: a call's rows over threads. A call runs in at most two parallel phases over bands of
// contiguous rows: the default near limit (each band's nearest key, reduced in band order) and
// then the rows. A pair's two eyes share each phase. Rows are independent and the reduction is the
// sequential one regrouped, so the output does not depend on the number of threads or bands, bit
// for bit.
#pragma once

#include "kernels/kernel_table.hpp"
#include "reproject/reproject.hpp"

namespace reproject {
namespace detail {

// Runs every row of `frame_count` frames (one, or a pair's two eyes: frames[0] left, frames[1]
// right) planned from one source with `options`; completes their near limit first when the
// options leave it to the data. `jobs` null: the library's pool with Options::threads. Returns
// cancelled when Options::cancel stopped it, out_of_memory when row scratch could not be had
// (rows, or the near pass, left undone either way).
Status run_frames(const KernelTable& kernels, Frame* frames, int frame_count, const Options& options,
                  const ParallelFor* jobs);

// Gives back every cached scratch set that no running call holds (reproject::release_memory).
void release_cached_scratch() noexcept;

}  // namespace detail
}  // namespace reproject
