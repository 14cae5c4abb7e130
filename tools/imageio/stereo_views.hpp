// Stereo outputs for viewing a left/right pair, and diagnostic images of a reprojection.
//
// Convention: colour values are 0..255 floats, the stored values of an 8-bit PNG as read_png
// returns them and write_png expects them, so a PNG pair can be composed and written back without
// rescaling. (Data in 0..1, e.g. from EXR, should be scaled by 255 first; the packings and the
// plain anaglyph only move values, but the Dubois anaglyph clamps to 0..255 and the status and
// heat-map colours are 0..255.)
//
// Inputs are ColorViews of 1-4 planar channels or interleaved RGBA; 1-2 channels are grey (+ alpha),
// 3-4 RGB (+ alpha). Outputs are planar Images. Failures are IoStatus values (invalid_argument for
// a bad view, size_mismatch for views that must have one size, out_of_memory); on failure `*out`
// is left empty.
#pragma once

#include <array>
#include <cstdint>

#include "imageio/imageio.hpp"
#include "reproject/image.hpp"

namespace reproject::io {

enum class StereoPacking : std::uint8_t {
  full,  // each eye at full resolution: the frame is twice as wide (or tall)
  half,  // each eye squeezed 2:1 by averaging pixel pairs, so the frame keeps the eye's size;
         // an odd last column (row) is kept as it is, so nothing is dropped
};

// Left eye on the left, right eye on the right. Both views must have the same size and channel
// count; the output has that channel count, width 2 W (full) or 2 ceil(W / 2) (half), height H.
IoStatus side_by_side(const ColorView& left, const ColorView& right, Image* out,
                      StereoPacking packing = StereoPacking::full);
// Left eye on top. Width W, height 2 H (full) or 2 ceil(H / 2) (half).
IoStatus top_bottom(const ColorView& left, const ColorView& right, Image* out,
                    StereoPacking packing = StereoPacking::full);

enum class AnaglyphMethod : std::uint8_t {
  plain,   // red from the left eye's red, green and blue from the right eye's: exact colours per
           // eye, strong retinal rivalry on saturated reds and cyans
  dubois,  // Dubois' least-squares projection for red-cyan glasses: less rivalry and ghosting,
           // somewhat duller colours; clamped to 0..255
};

// A 3-channel red (left) / cyan (right) anaglyph. The views must have the same size; alpha is
// ignored and grey views count as R = G = B.
//
// Dubois: out = clamp(ML * left_rgb + MR * right_rgb, 0, 255), with the matrices E. Dubois
// published for red-cyan glasses on a typical display ("A projection method to generate anaglyph
// stereo images", ICASSP 2001; the red-cyan coefficients of his "least squares how-to" note). They
// are the least-squares fit of the glasses' and display's spectra, each output row normalised so
// that white in both eyes gives white. They are applied to the values as stored (gamma-encoded),
// as is common practice; strictly the fit assumes linear light.
IoStatus anaglyph(const ColorView& left, const ColorView& right, Image* out,
                  AnaglyphMethod method = AnaglyphMethod::dubois);

// Row r, column c of Dubois' left (right) matrix: the weight of input channel c in output channel r.
extern const float kDuboisLeft[3][3];
extern const float kDuboisRight[3][3];

// The colour a status byte is drawn in (0..255 RGB):
//   hit     (0)  black        (0, 0, 0)       — the usual case recedes
//   hole    (1)  red          (255, 0, 0)
//   outside (2)  sky blue     (0, 128, 255)
//   clipped (3)  yellow       (255, 255, 0)
//   any other value: magenta  (255, 0, 255)   — not a PixelStatus: a bug or uninitialised plane
std::array<float, 3> status_color(std::uint8_t status) noexcept;

// A 3-channel image of a status plane (PixelStatus bytes) in the colours above.
IoStatus status_image(const PlaneView<const std::uint8_t>& status, Image* out);
inline IoStatus status_image(const BytePlane& status, Image* out) {
  return status_image(PlaneView<const std::uint8_t>{status.data, status.width, status.height, status.stride}, out);
}

// The heat-map colour ramp at t in [0, 1] (clamped), 0..255 RGB: black -> red -> yellow -> white,
// linear in thirds: R = 3t, G = 3t - 1, B = 3t - 2, each clamped to [0, 1], times 255. Every
// channel is non-decreasing in t and their sum strictly increasing, so more error is always
// brighter. NaN gives magenta (255, 0, 255), outside the ramp.
std::array<float, 3> heat_color(float t) noexcept;

// A 3-channel heat map of the per-pixel error max_c |a_c - b_c| (over all channels, alpha
// included), through heat_color(error / max_error). `a` and `b` must have the same size and
// channel count (a single plane: ColorView::planar({plane})). max_error > 0 fixes the scale (an
// error at or above it is white); max_error == 0 takes the largest finite error of the image
// (all black if there is none). Negative or non-finite max_error is invalid. A pixel whose error is
// NaN (NaN input, inf - inf) is magenta.
IoStatus error_heat_map(const ColorView& a, const ColorView& b, Image* out, float max_error = 0.0f);

}  // namespace reproject::io
