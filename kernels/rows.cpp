// The row driver (kernels/rows.hpp): decode, search and resolve, row by row.
#include "kernels/rows.hpp"

#include <algorithm>

#include "kernels/depth_formats.hpp"

namespace reproject::detail {
namespace {

// Whether the decode keeps the row's stored depth values for the resolve (RowScratch::stored_depth).
bool stores_depth_values(const Frame& f) {
  return f.depth_out.data != nullptr && depth_row_kept(f);
}

void pad_parallax_row(const Frame& f, float* parallax) {
  std::fill(parallax - f.pad_left, parallax, parallax[0]);
  std::fill(parallax + f.source_width, parallax + f.source_width + f.pad_right, parallax[f.source_width - 1]);
}

// Row y of f once its parallax row (`parallax` = scratch.parallax, columns [0, Ws)) holds the
// decode.
void search_and_resolve(const Frame& f, const KernelTable& kernels, RowScratch& scratch, float* parallax, int y) {
  pad_parallax_row(f, parallax);
  if (f.method == Method::single && kernels.single_and_resolve) {
    kernels.single_and_resolve(f, y, scratch);
    return;
  }
  if (f.method == Method::march16 && kernels.march16_and_resolve) {
    kernels.march16_and_resolve(f, y, scratch);
    return;
  }
  kernels.search[static_cast<int>(f.method)](f, scratch);
  kernels.resolve(f, y, scratch);
}

}  // namespace

float nearest_key_in_rows(const Frame& f, const KernelTable& kernels, int row_begin, int row_end) {
  // Decoded with the same kernels (and FMA policy) as the rows.
  float nearest = f.key_far;
  for (int y = row_begin; y < row_end; ++y) nearest = std::max(nearest, kernels.nearest_key(f, f.depth.row(y)));
  return nearest;
}

void run_rows(const Frame& f, const KernelTable& kernels, RowScratch& scratch, int row_begin, int row_end) {
  float* parallax = scratch.parallax_storage.data() + f.pad_left;
  scratch.parallax = parallax;
  float* stored = stores_depth_values(f) ? scratch.stored_depth.data() : nullptr;
  for (int y = row_begin; y < row_end; ++y) {
    kernels.decode(f, f.depth.row(y), parallax, stored);
    search_and_resolve(f, kernels, scratch, parallax, y);
  }
}

void run_pair_rows(const Frame& left, const Frame& right, const KernelTable& kernels, RowScratch& scratch,
                   int row_begin, int row_end) {
  // Column 0 at the same place for both eyes: prepare_scratch sized the storage for the widest
  // padding on either side, and each eye's own padding is no wider.
  float* parallax = scratch.parallax_storage.data() + std::max(left.pad_left, right.pad_left);
  scratch.parallax = parallax;
  const bool mirrored = mirrored_eyes(left, right);
  float* stored = stores_depth_values(left) || stores_depth_values(right) ? scratch.stored_depth.data() : nullptr;
  for (int y = row_begin; y < row_end; ++y) {
    // Each source row is read from memory once and decoded once: the left eye's model is the
    // right's mirror (-a, -b), so its decode is the negation of the right eye's, bit for bit
    // (the decode constants are exact negations, rounding is symmetric, both eyes' keys s * p are
    // equal, so the clamps pick the same branch; zeros are +0 on both sides, hence 0 - p). The
    // left eye's colour reads then hit the rows the right eye's resolve has just read.
    const std::uint8_t* depth = right.depth.row(y);
    // The stored values are the same for both eyes: the right eye's decode writes them for both.
    kernels.decode(right, depth, parallax, stored);
    search_and_resolve(right, kernels, scratch, parallax, y);
    if (mirrored) {
      for (int x = 0; x < right.source_width; ++x) parallax[x] = 0.0f - parallax[x];
    } else {
      kernels.decode(left, depth, parallax, stored);
    }
    search_and_resolve(left, kernels, scratch, parallax, y);
  }
}

}  // namespace reproject::detail
