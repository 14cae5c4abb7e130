// The stereo pipeline around reprojection (docs/DESIGN.md §3, §4, §5): what an engine that synthesises
// an eye also needs. Each function is independent of the kernels; all of them use the same
// conventions (view space x right, y up, z forward = the positive distance of DESIGN §3; pixel i
// of a row has its centre at x = i, DESIGN §2) and the same standard stereo projection (DESIGN §4:
// clip.x += side * S * (clip.w - c), side = -1 left, +1 right).
//
//   parallax_budget         min/max/percentiles of a depth buffer's parallax, comfort shares, histogram
//   stereo_culling_frustum  one frustum that holds both eyes' frusta (cull once for two eyes)
//   pick                    depth and both eyes' positions under a cursor, from the eyes' depth buffers
//   make_screen_to_view     precision-preserving screen -> view-space reconstruction (scale and bias)
//   place_at_depth          stereo clip positions of a 2D element (cursor, label, HUD) at a depth
//   dilate_nearer_depth     halo-reduction pre-filter: horizontal dilation of the nearer depth
//
// Every function validates its inputs once and returns a Status; none throws and none allocates
// inside its per-pixel loops.
#pragma once

#include <cstdint>
#include <optional>

#include "reproject/depth.hpp"
#include "reproject/image.hpp"
#include "reproject/parallax.hpp"
#include "reproject/status.hpp"

namespace reproject {

// ---------------------------------------------------------------------------------------------
// 1. Parallax budget (DESIGN §4)

// The percentiles a budget reports, in percent.
constexpr int kBudgetPercentileCount = 7;
constexpr double kBudgetPercentiles[kBudgetPercentileCount] = {1.0, 5.0, 25.0, 50.0, 75.0, 95.0, 99.0};

struct BudgetOptions {
  // E = interocular / physical screen width: the viewer's real eye separation as a fraction of the
  // screen (e.g. 0.065 m / 0.6 m). Unset: the camera's separation S (DESIGN §4's comfort rule is
  // S <= E, so that is the largest screen on which the content still meets it).
  std::optional<double> eye_separation;
  // Pixels the image spans on that screen. 0: the depth plane's width.
  int display_width = 0;
  // |p| above this many pixels is out of the comfortable range. Unset: E * display_width, the
  // on-screen parallax at which the eyes' lines of sight are parallel.
  std::optional<double> parallax_limit;
  // Histogram of the parallax: `histogram_bins` equal bins over [histogram_min, histogram_max]
  // pixels (both set, min < max), or over the finite parallax present (both unset).
  int histogram_bins = 0;
  std::optional<double> histogram_min;
  std::optional<double> histogram_max;
};

// Parallax is left eye -> right eye (sigma = +1), in pixels of the display width W:
// p = S W (1 - c / z). "of eyes" values are p / (E W): 1 means the eyes are parallel.
struct ParallaxBudget {
  std::int64_t pixels = 0;      // pixels measured (all of the plane)
  std::int64_t unreadable = 0;  // NaN, or decoding to w < 0: measured as infinitely far, as the kernels read them
  int display_width = 0;        // W used
  double eye_separation = 0.0;  // E used
  double eye_parallax = 0.0;    // E * W: the parallax of parallel eyes, pixels
  double parallax_limit = 0.0;  // the limit used, pixels

  // Pixels (NaN when the plane is empty). Percentile q: the order statistic at rank
  // q/100 * (pixels - 1), linearly interpolated between its two neighbours.
  double min = 0.0;
  double max = 0.0;
  double percentile[kBudgetPercentileCount] = {};
  // The same divided by E * W.
  double min_of_eyes = 0.0;
  double max_of_eyes = 0.0;
  double percentile_of_eyes[kBudgetPercentileCount] = {};

  // Shares of `pixels` (0..1) out of the comfortable range; a pixel can count in several.
  double beyond_limit = 0.0;     // |p| > parallax_limit
  double nearer_than_half_convergence = 0.0;   // z < c / 2   (p < -S W)
  double farther_than_100_convergence = 0.0;   // z > 100 c   (incl. infinity and unreadable)
  double uncomfortable = 0.0;                   // any of the three

  // The histogram's range and the pixels outside it (the counts themselves are the caller's array).
  double histogram_min = 0.0;
  double histogram_max = 0.0;
  std::int64_t below_histogram = 0;
  std::int64_t above_histogram = 0;
};

// The parallax budget of a depth buffer under a stereo camera (DESIGN §4). Each stored value d is
// decoded to w = 1/z by the shared decoder (DESIGN §3; NaN and w < 0 count as w = 0, infinitely
// far, as the kernels read them), then p = S W (1 - c w) in double: the left->right parallax in
// display pixels (z is the same in every eye, so this holds whichever eye's buffer it is). Reports
// min, max and kBudgetPercentiles of p, in pixels and as a fraction of E W; the shares beyond the
// parallax limit, nearer than c/2, farther than 100 c and any of them; and the count of p in each
// of options.histogram_bins equal bins of width h over [lo, hi] (bin i covers [lo + i h,
// lo + (i+1) h), the last one closed at hi) into `histogram`, which must hold that many counters
// when bins > 0. Exact percentiles need the values in order: the call allocates one float per
// pixel once (nothrow; invalid_size if that fails), outside its loops.
Status parallax_budget(const FloatPlane& depth, const DepthDecoder& decoder, const StereoCamera& camera,
                       const BudgetOptions& options, ParallaxBudget* out,
                       std::int64_t* histogram = nullptr) noexcept;

// ---------------------------------------------------------------------------------------------
// Frusta (shared by culling and reconstruction)

// A view frustum in view space (x right, y up, z forward). Perspective: its side edges meet the
// plane z = near_plane at x = left, right and y = bottom, top (glFrustum's numbers); far_plane may
// be +inf. Orthographic: the box x in [left, right], y in [bottom, top], z in [near, far].
struct ViewFrustum {
  double left = -1.0;
  double right = 1.0;
  double bottom = -1.0;
  double top = 1.0;
  double near_plane = 1.0;
  double far_plane = 1000.0;
  bool orthographic = false;

  // Symmetric perspective frustum with square pixels: right = near tan(fov/2), top = right * height / width;
  // horizontal_fov in radians (0 < fov < pi), near and far in view-space units.
  static ViewFrustum perspective(double horizontal_fov, int width, int height, double near_plane,
                                 double far_plane) noexcept;
  // invalid_option unless every number is finite (far may be +inf for perspective), left < right,
  // bottom < top, 0 < near < far (orthographic: 0 <= near < far, finite).
  Status validate() const noexcept;
};

// ---------------------------------------------------------------------------------------------
// 2. Stereo culling frustum (DESIGN §4)

struct CullingFrustum {
  double pull_back = 0.0;  // Z = c / (1 + 1/S) = S c / (1 + S)
  // The culling camera's centre of projection, in the mono view space: the mono frustum's centre
  // ray pulled back by Z, -Z * ((l + r) / 2n, (b + t) / 2n, 1); (0, 0, -Z) for a symmetric frustum.
  double origin[3] = {};
  // The culling camera's frustum in its own frame (the mono axes, origin at `origin`): horizontal
  // edges widened by S times the mono half-width on each side, the vertical ones unchanged, its
  // near and far planes the mono ones (distances near + Z, far + Z).
  ViewFrustum frustum;
  // The same volume as planes in the mono view space: (a, b, c, d) with a x + b y + c z + d >= 0
  // inside, unit normals; left, right, bottom, top, near, far. An infinite far plane is (0, 0, 0, 1).
  double planes[6][4] = {};

  // Whether a mono view-space point is inside every plane, with `slack` view-space units to spare.
  bool contains(double x, double y, double z, double slack = 0.0) const noexcept;
};

// The frustum that contains both eyes' frusta of the standard stereo projection (DESIGN §4), so a
// scene is culled once for two eyes. The eye with side s sees x in [s T + (L - s S h) z,
// s T + (R - s S h) z] (L, R the mono edge tangents l/n, r/n, h = (R - L)/2, T = S h c the half
// interaxial, StereoCamera::eye_translation): the union of the two is bounded on the left by the
// line through the left eye (-T, 0) parallel to the right eye's left edge, and mirrored on the
// right. The two lines meet at z = -Z, Z = c / (1 + 1/S): the culling camera is the mono one pulled
// back by Z with tangents L - S h, R + S h (vertical ones and near/far unchanged). Horizontally,
// for z >= 0, it is the convex hull of the two eyes' viewing cones: each side plane passes through
// one eye's centre of projection and is parallel to the other eye's edge, so no convex volume
// that holds both is narrower (with a near plane n > 0 the sides leave at most 2 S h n of slack
// there). Top and bottom keep the eyes' slopes from the pulled-back origin: attained at infinity,
// Z (t - b) / 2n looser at the eyes. Perspective mono frusta only (invalid_option for orthographic).
Status stereo_culling_frustum(const ViewFrustum& mono, const StereoCamera& camera, CullingFrustum* out) noexcept;

// ---------------------------------------------------------------------------------------------
// 3. Picking under a cursor (DESIGN §4, §5)

struct PickOptions {
  // Largest crossed parallax (pixels, >= 0, left->right) the search allows, as
  // Options::max_negative_parallax. Unset: the nearest parallax in either eye's row.
  std::optional<float> max_negative_parallax;
  // An eye's answer is on a wall (a silhouette: that eye does not see the point) when its segment
  // [j, j+1] changes the eye->mono parallax p/2 by more than this many pixels (Options::hole_threshold).
  float hole_threshold = 1.0f;
  // Pixels of parallax within which two readings agree: the two eyes' answers, and an eye's answer
  // with the other eye's buffer at the same point (the cross-check of pick()).
  float agreement = 0.25f;
};

enum class PickSource : std::uint8_t {
  both,   // both eyes see the point and agree on its parallax: the mean of the two
  left,   // only the left eye's answer stands (the right one is on a wall, off the row, clipped or
          // contradicted by the left buffer): the point is hidden from the right eye
  right,  // only the right eye's
  none,   // neither answer stands: the nearer one, unreliable
};
// Short stable name: "both", "left", "right", "none".
const char* to_string(PickSource source) noexcept;

struct PickResult {
  PickSource source = PickSource::none;
  double parallax = 0.0;       // p, left -> right, pixels
  double inverse_depth = 0.0;  // w = (p - a) / b, the decoder's units (disparity: the disparity)
  double depth = 0.0;          // z = 1 / w (+inf at infinity)
  double left_x = 0.0;         // the point's column in the left eye: cursor_x - p / 2
  double right_x = 0.0;        // in the right eye: cursor_x + p / 2
  double left_parallax = 0.0;  // each eye's own answer, whatever its kind (the crossing of its search)
  double right_parallax = 0.0;
};

// What is under a cursor at mono (cyclopean, centre-eye) column cursor_x of row cursor_y, from the
// left and right eyes' depth buffers (same size and encoding) and the left->right parallax model.
// A point at parallax p seen at mono x is at x - p/2 in the left eye and x + p/2 in the right
// (DESIGN §4 with sigma = -1/2, +1/2). Symmetric search: the ray of the cursor is the line
// x_left = u - o, x_right = u + o, o = p/2 from the nearest allowed parallax to p = a (infinity); in
// each eye it is DESIGN §5's exact search (rows read by linear interpolation, clamped beyond the
// ends): the first offset where the ray reaches that eye's surface, P_eye(u -/+ o) = 2 o. An
// answer stands when it is not on a wall, on the row, not clipped, and the other eye's buffer does
// not contradict it (at u +/- p/2 the other eye must see parallax p, or something nearer that hides
// it, to within options.agreement). Where both stand and agree, the result is their mean; where
// one eye sees past a silhouette, the other eye's (PickSource). model.b must not be 0 (depth would
// not matter). Cost: O(parallax range) reads of two rows; nothing is allocated.
Status pick(const FloatPlane& left_depth, const FloatPlane& right_depth, const DepthDecoder& decoder,
            const ParallaxModel& left_to_right, double cursor_x, int cursor_y, const PickOptions& options,
            PickResult* out) noexcept;

// ---------------------------------------------------------------------------------------------
// 4. Screen -> view-space reconstruction (DESIGN §3)

struct ViewPoint {
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;  // the positive view distance (GL eye space has z_eye = -z)
};

// Scale and bias constants of one frustum and viewport, public so that a shader can take them.
// u = (pixel_x + 0.5) / width in [0, 1] from the left edge, v = (pixel_y + 0.5) / height from the
// top edge (DESIGN §2's pixel centres). Perspective (w from the decoder, DESIGN §3):
//   x_v = (x_bias + pixel_x * x_scale) / w,   y_v = (y_bias + pixel_y * y_scale) / w,   z_v = 1 / w
// with x_bias + pixel_x * x_scale = (l + u (r - l)) / n (and y from t towards b), i.e.
// x_v = (l + u (r - l)) z_v / n with the division by w done once. Linear depth: the same times z_v = d.
// Orthographic: x_v = x_bias + pixel_x * x_scale = l + u (r - l) (no depth), z_v = z_bias + d z_scale.
struct ScreenToView {
  bool orthographic = false;
  int width = 0;
  int height = 0;
  float x_scale = 0.0f, x_bias = 0.0f;
  float y_scale = 0.0f, y_bias = 0.0f;
  DepthDecoder decoder;              // perspective: stored value -> w
  float z_scale = 0.0f, z_bias = 0.0f;  // orthographic: stored value -> z

  // The view-space point at continuous pixel coordinates (pixel centres at integers) with stored
  // depth d. No checks: the object comes from make_screen_to_view.
  ViewPoint at_pixel(float pixel_x, float pixel_y, float stored) const noexcept;
};

// Builds the constants from the frustum's edges in double, each rounded to float once, instead of
// inverting a concatenated (viewport x projection [x view]) matrix, whose float inverse mixes large
// and small terms and loses the far, off-origin points (DESIGN §3's precision rule). Perspective
// takes every encoding but disparity (n, f from the frustum); orthographic stores z affinely, so it
// takes linear (d = z), standard (z = n + d (f - n)), reversed (z = f - d (f - n)) and gl_ndc
// (z = (f + n)/2 + d (f - n)/2).
Status make_screen_to_view(const ViewFrustum& frustum, DepthEncoding encoding, int width, int height,
                           ScreenToView* out) noexcept;

// ScreenToView::at_pixel at every pixel centre of `depth` (DESIGN §2, §3): x(i, j) = at_pixel(i, j,
// depth(i, j)).x, and y, z likewise, into three float planes of depth's size, which must be the
// reconstruction's width x height. The outputs may overlap neither the depth nor each other.
Status screen_to_view(const ScreenToView& reconstruction, const FloatPlane& depth, const MutableFloatPlane& x,
                      const MutableFloatPlane& y, const MutableFloatPlane& z) noexcept;

// ---------------------------------------------------------------------------------------------
// 5. 2D elements at a depth (DESIGN §4)

struct ClipPosition {
  float x = 0.0f, y = 0.0f, z = 0.0f, w = 1.0f;
};

// The clip positions, for each eye, of a screen-space element (cursor, label, HUD vertex) that sits
// at mono NDC (ndc_x, ndc_y) and is to be seen at view depth z (> 0, +inf allowed). The standard
// stereo projection's shear at clip.w = z, divided by w (DESIGN §4):
//   left:  (ndc_x - S (1 - c/z), ndc_y, d, 1)     right: (ndc_x + S (1 - c/z), ndc_y, d, 1)
// with d = decoder.encode(z), the stored depth (NDC z for standard/gl_ndc/reversed/...), so it
// depth-tests against the scene. The eyes' images are then p = S W (1 - c/z) pixels apart for an
// image W pixels wide (zero at z = c: HUD at the convergence plane) and their mean is the mono
// position. w = 1; scale all four by a positive w if the pipeline wants clip.w = z. Either output
// may be null, not both; the decoder must not be disparity.
Status place_at_depth(double ndc_x, double ndc_y, double z, const StereoCamera& camera, const DepthDecoder& decoder,
                      ClipPosition* left, ClipPosition* right) noexcept;

// ---------------------------------------------------------------------------------------------
// 6. Halo-reduction pre-filter (DESIGN §5)

// out(x, y) = depth(x', y) for the x' in [x - radius, x + radius] (within the row) whose decoded
// inverse depth w is largest: the nearer surface, for every encoding (larger w = nearer:
// DESIGN §3); NaN and w < 0 never win (a window of only those keeps its own value); ties keep the leftmost.
// Applied to the source depth before reprojection, it moves each silhouette's edge pixels (whose
// colour is partly foreground, from anti-aliasing, while their depth is the background's) with the
// foreground, so they no longer land on the background as a halo or seed a hole fill (DESIGN §5's
// "repeat background") with foreground colour. radius >= 0 (0 copies). `out` has depth's size and
// must not overlap it.
Status dilate_nearer_depth(const FloatPlane& depth, const DepthDecoder& decoder, int radius,
                           const MutableFloatPlane& out) noexcept;

}  // namespace reproject
