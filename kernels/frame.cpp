// The stages every method shares: the plan, the per-row parallax decode and the resolve stage
// (DESIGN §5–§6 "One resolve stage for all"), and the row driver.
#include "kernels/frame.hpp"

#include <algorithm>
#include <limits>

#include "kernels/frame_rows.hpp"
#include "kernels/secant.hpp"

namespace reproject {
namespace detail {
namespace {

float clampf(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }

void pad_parallax_row(const Frame& f, float* parallax) {
  std::fill(parallax - f.pad_left, parallax, parallax[0]);
  std::fill(parallax + f.source_width, parallax + f.source_width + f.pad_right, parallax[f.source_width - 1]);
}

// Reads channel c of source pixel i and writes target pixel t, for either layout.
struct RowIo {
  const float* src[4];
  float* dst[4];
  int channels;
  int pixel_step;  // 1 planar, 4 interleaved

  RowIo(const Frame& f, int y) {
    channels = f.source.color.channels;
    const bool interleaved = f.source.color.layout == ColorLayout::interleaved_rgba;
    pixel_step = interleaved ? 4 : 1;
    for (int c = 0; c < channels; ++c) {
      const int plane = interleaved ? 0 : c;
      const int offset = interleaved ? c : 0;
      src[c] = f.source.color.plane[plane].row(y) + offset;
      dst[c] = f.target.color.plane[plane].row(y) + offset;
    }
  }
  float source(int c, int i) const { return src[c][static_cast<std::ptrdiff_t>(i) * pixel_step]; }
  float& target(int c, int t) const { return dst[c][static_cast<std::ptrdiff_t>(t) * pixel_step]; }
};

// Output depth between two stored values, in the space where a plane is linear: the stored value
// for affine encodings, 1/d for linear depth.
template <class Fma>
float interpolate_depth(const Frame& f, float d0, float d1, float frac) {
  if (f.affine) return madd<Fma>(frac, d1 - d0, d0);
  const float w0 = 1.0f / d0;
  const float w1 = 1.0f / d1;
  return 1.0f / madd<Fma>(frac, w1 - w0, w0);
}

}  // namespace

template <class Fma>
void decode_parallax_columns(const Frame& f, const float* depth, float* parallax, int begin, int end) {
  for (int i = begin; i < end; ++i) parallax[i] = decode_parallax<Fma>(f, depth[i]);
}

template <class Fma>
float nearest_key_in_columns(const Frame& f, const float* depth, int begin, int end, float nearest) {
  for (int i = begin; i < end; ++i) nearest = std::max(nearest, f.s * decode_parallax<Fma>(f, depth[i]));
  return nearest;
}

template <class Fma>
void resolve_pixels(const Frame& f, int y, const RowScratch& scratch, int t_begin, int t_end) {
  const RowIo io(f, y);
  const float* parallax = scratch.parallax;
  const float* depth = f.source.depth.row(y);
  float* depth_out = f.target.depth.data ? f.target.depth.row(y) : nullptr;
  std::uint8_t* status_out = f.target.status.data ? f.target.status.row(y) : nullptr;
  float* x_out = f.target.source_x.data ? f.target.source_x.row(y) : nullptr;
  const int last = f.source_width - 1;
  const float last_column = static_cast<float>(last);

  for (int t = t_begin; t < t_end; ++t) {
    const float x = scratch.source_x[t];
    PixelStatus status;
    // Interpolation between columns j0 and j1 at `frac`; a fill copies column j0 (frac 0).
    int j0;
    int j1;
    float frac;
    bool write = true;
    bool black = false;
    if (scratch.clipped[t] || x < 0.0f || x > last_column) {
      status = scratch.clipped[t] ? PixelStatus::clipped : PixelStatus::outside;
      float xs = x;
      if (status == PixelStatus::outside) {
        write = f.edge != EdgeMode::none;
        black = f.edge == EdgeMode::black;
        // Reflected about the edge pixel's centre (then clamped, if still off the row).
        if (f.edge == EdgeMode::mirror) xs = x < 0.0f ? -x : (last_column - x) + last_column;
      }
      const float xc = clampf(xs, 0.0f, last_column);
      j0 = static_cast<int>(std::floor(xc));
      j1 = std::min(j0 + 1, last);
      frac = xc - static_cast<float>(j0);
    } else {
      j0 = static_cast<int>(std::floor(x));
      j1 = std::min(j0 + 1, last);
      frac = x - static_cast<float>(j0);
      if (parallax[j1] - parallax[j0] > f.hole_threshold) {
        // A wall (§5): the farther endpoint has the smaller key s * p.
        status = PixelStatus::hole;
        const bool j1_farther = f.s * parallax[j1] < f.s * parallax[j0];
        const int farther = j1_farther ? j1 : j0;
        const int nearer = j1_farther ? j0 : j1;
        j0 = j1 = f.hole_fill == HoleFill::foreground ? nearer : farther;
        frac = 0.0f;
        write = f.hole_fill != HoleFill::none;
      } else {
        status = PixelStatus::hit;
      }
    }
    if (write) {
      for (int c = 0; c < io.channels; ++c) {
        const float c0 = io.source(c, j0);
        io.target(c, t) = black ? 0.0f : madd<Fma>(frac, io.source(c, j1) - c0, c0);
      }
      if (depth_out) depth_out[t] = interpolate_depth<Fma>(f, depth[j0], depth[j1], frac);
    }
    if (status_out) status_out[t] = static_cast<std::uint8_t>(status);
    if (x_out) x_out[t] = x;
  }
}

template void decode_parallax_columns<Fused>(const Frame&, const float*, float*, int, int);
template void decode_parallax_columns<Unfused>(const Frame&, const float*, float*, int, int);
template float nearest_key_in_columns<Fused>(const Frame&, const float*, int, int, float);
template float nearest_key_in_columns<Unfused>(const Frame&, const float*, int, int, float);
template void resolve_pixels<Fused>(const Frame&, int, const RowScratch&, int, int);
template void resolve_pixels<Unfused>(const Frame&, int, const RowScratch&, int, int);

namespace {

// The scalar references as whole-row kernels.
template <class Fma>
void scalar_decode(const Frame& f, const float* depth, float* parallax) {
  decode_parallax_columns<Fma>(f, depth, parallax, 0, f.source_width);
}
template <class Fma>
float scalar_nearest_key(const Frame& f, const float* depth) {
  return nearest_key_in_columns<Fma>(f, depth, 0, f.source_width, f.key_far);
}
template <class Fma, void (*Search)(const Frame&, RowScratch&, int, int)>
void scalar_search(const Frame& f, RowScratch& scratch) {
  Search(f, scratch, 0, f.target_width);
}
template <class Fma>
void scalar_resolve(const Frame& f, int y, const RowScratch& scratch) {
  resolve_pixels<Fma>(f, y, scratch, 0, f.target_width);
}
template <class Fma>
KernelTable make_scalar_table(const char* name) {
  KernelTable table{};
  table.name = name;
  table.decode = scalar_decode<Fma>;
  table.nearest_key = scalar_nearest_key<Fma>;
  table.search[static_cast<int>(Method::scanline)] = scalar_search<Fma, search_row_scanline<Fma>>;
  table.search[static_cast<int>(Method::march16)] = scalar_search<Fma, search_row_march<Fma>>;
  table.search[static_cast<int>(Method::single)] = scalar_search<Fma, search_row_single<Fma>>;
  table.search[static_cast<int>(Method::secant)] = scalar_search<Fma, search_row_secant<Fma>>;
  table.search[static_cast<int>(Method::exact)] = scalar_search<Fma, search_row_exact<Fma>>;
  table.resolve = scalar_resolve<Fma>;
  return table;
}

// Scratch for the calling thread, reused across rows and calls (the sequential make_frame() and
// run_rows(); the threaded calls bring their own).
RowScratch& thread_scratch(const Frame& f) {
  thread_local RowScratch scratch;
  prepare_scratch(f, scratch);
  scratch.parallax = scratch.parallax_storage.data() + f.pad_left;
  return scratch;
}

}  // namespace

const KernelTable& scalar_kernels(bool fused) {
  static const KernelTable fused_table = make_scalar_table<Fused>("scalar");
  static const KernelTable unfused_table = make_scalar_table<Unfused>("scalar-unfused");
  return fused ? fused_table : unfused_table;
}

Frame plan_frame(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target) {
  Frame f;
  f.source = source;
  f.target = target;
  f.source_width = source.depth.width;
  f.height = source.depth.height;
  f.guard = options.guard;
  f.target_width = f.source_width - 2 * options.guard;

  f.a = model.a;
  f.b = model.b;
  f.affine = decoder.is_affine();
  if (f.affine) {
    // Rounded to float once, and clamped to the float range: with an absurd model (convergence
    // 1e37, say) b A overflows, and inf - inf would decode ordinary depths to NaN ("infinitely
    // far"). Clamped, they decode to parallax far beyond L, which is what the model means.
    const double largest = std::numeric_limits<float>::max();
    f.decode_scale = static_cast<float>(std::clamp(static_cast<double>(model.b) * decoder.A(), -largest, largest));
    f.decode_offset = static_cast<float>(
        std::clamp(static_cast<double>(model.a) + static_cast<double>(model.b) * decoder.B(), -largest, largest));
  }
  f.s = model.b > 0.0f ? 1.0f : -1.0f;
  f.limit = static_cast<float>(f.source_width + 2);
  f.p_far = clampf(model.a, -f.limit, f.limit);
  f.key_far = f.s * f.p_far;

  f.hole_threshold = options.hole_threshold;
  f.hole_fill = options.hole_fill;
  f.edge = options.edge;
  f.method = options.method;
  f.march_steps = options.march_steps;
  f.probe = options.probe_parallax ? clampf(*options.probe_parallax, -f.limit, f.limit) : f.p_far;
  f.secant_max_steps = options.secant_max_steps;

  f.near_from_frame = !options.max_negative_parallax;
  if (options.max_negative_parallax)
    set_near_key(f, std::max(std::min(*options.max_negative_parallax, f.limit), f.key_far));
  else if (!near_pass_needed(f))
    set_near_key(f, f.limit);  // nothing is nearer than L: nothing is clipped, as the frame's own limit says
  return f;
}

bool near_pass_needed(const Frame& f) {
  // `single` and `exact` neither start a search at the near end nor (with the frame's own near
  // limit) clip anything, so they skip the pass over the depth that finds it.
  return f.near_from_frame && f.method != Method::single && f.method != Method::exact;
}

void set_near_key(Frame& f, float key_near) {
  f.key_near = key_near;
  f.p_near = f.s * f.key_near;
  f.march_step = (f.p_far - f.p_near) / static_cast<float>(f.march_steps);

  // Columns a search may read: x = t' - p for t' in [guard, guard + Wt - 1] and p between the
  // extremes below, plus one column for interpolation and one for rounding. Without a near pass
  // no search reads at the near end (single, exact with the frame's own limit).
  const float p_read = near_pass_needed(f) || !f.near_from_frame ? f.p_near : f.p_far;
  const float p_max = std::max({p_read, f.p_far, f.probe});
  const float p_min = std::min({p_read, f.p_far, f.probe});
  f.pad_left = static_cast<int>(std::max(0.0f, std::ceil(p_max - static_cast<float>(f.guard)))) + 2;
  f.pad_right = static_cast<int>(std::max(0.0f, std::ceil(-p_min - static_cast<float>(f.guard)))) + 3;
}

float nearest_key_in_rows(const Frame& f, const KernelTable& kernels, RowScratch& scratch, int row_begin,
                          int row_end) {
  // Decoded with the same kernels (and FMA policy) as the rows.
  (void)scratch;
  float nearest = f.key_far;
  for (int y = row_begin; y < row_end; ++y) nearest = std::max(nearest, kernels.nearest_key(f, f.source.depth.row(y)));
  return nearest;
}

void prepare_scratch(const Frame& f, RowScratch& scratch) {
  // Every parallax the plan holds (p_near, p_far, probe) lies in [-limit, limit], so this is
  // set_near_key()'s padding at its widest.
  const int pad = static_cast<int>(std::max(0.0f, std::ceil(f.limit - static_cast<float>(f.guard))));
  const std::size_t padded = static_cast<std::size_t>(pad + 2) + f.source_width + static_cast<std::size_t>(pad + 3);
  if (scratch.parallax_storage.size() < padded) scratch.parallax_storage.resize(padded);
  if (scratch.source_x.size() < static_cast<std::size_t>(f.target_width)) {
    scratch.source_x.resize(f.target_width);
    scratch.clipped.resize(f.target_width);
  }
  // `secant` sizes its block table itself on first use; doing it here keeps that first use from
  // allocating inside a row on whichever thread happens to run it.
  const std::size_t blocks = static_cast<std::size_t>((f.source_width + kSecantBlock - 1) / kSecantBlock);
  if (scratch.block_min.size() < blocks) {
    scratch.block_min.resize(blocks);
    scratch.block_max.resize(blocks);
  }
}

Frame make_frame(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target, const KernelTable& kernels) {
  Frame f = plan_frame(source, decoder, model, options, target);
  // The nearest key s * p in the whole frame: the default near end of every ray (DESIGN §5), so
  // that nothing is clipped.
  if (near_pass_needed(f))
    set_near_key(f, nearest_key_in_rows(f, kernels, thread_scratch(f), 0, f.height));
  return f;
}

void run_rows(const Frame& f, const KernelTable& kernels, RowScratch& scratch, int row_begin, int row_end) {
  scratch.parallax = scratch.parallax_storage.data() + f.pad_left;
  float* parallax = scratch.parallax_storage.data() + f.pad_left;
  const SearchRow search = kernels.search[static_cast<int>(f.method)];
  for (int y = row_begin; y < row_end; ++y) {
    kernels.decode(f, f.source.depth.row(y), parallax);
    pad_parallax_row(f, parallax);
    search(f, scratch);
    kernels.resolve(f, y, scratch);
  }
}

void run_rows(const Frame& f, const KernelTable& kernels, int row_begin, int row_end) {
  run_rows(f, kernels, thread_scratch(f), row_begin, row_end);
}

}  // namespace detail
}  // namespace reproject
