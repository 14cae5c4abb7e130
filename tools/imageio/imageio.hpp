// Image files for the tests and the tools (not part of the kernel library): PNG through libpng,
// PFM by hand, OpenEXR through the OpenEXR library, and a generic front end that picks the format
// by the file name's extension.
//
// Pixels are planar reproject::Image float planes holding the stored values: PNG's integers
// (0..255 or 0..65535), PFM's and EXR's floats (half channels widened to float). Nothing is
// rescaled, gamma-corrected or colour-managed.
//
// Every function reports failure as a value and nothing throws out of it. Writers build the file
// under a temporary name next to the destination and rename it into place only once it is
// complete, so a failed write leaves neither a partial file nor a changed destination.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <cstdio>
#include <string>
#include <vector>

#include "reproject/image.hpp"

namespace reproject::io {

enum class IoError : std::uint8_t {
  none = 0,
  invalid_argument,  // a null output, an empty image, an unsupported channel count or bit depth
  open_failed,       // the file cannot be opened (missing, no permission, ...)
  read_failed,       // reading failed (an I/O error, a directory, ...)
  not_this_format,   // the file is not of the format read (e.g. no PNG signature), unknown extension
  truncated,         // the file ends before the image does
  corrupt,           // the format's decoder rejected the data (CRC error, bad chunk, bad header, ...)
  unsupported,       // valid data this reader does not handle (a channel layout, the size limit)
  out_of_memory,
  write_failed,      // creating, writing or renaming the output failed
  size_mismatch,     // images (or planes) that must have one size do not
};
const char* to_string(IoError error) noexcept;

// The result of every call: ok, or what went wrong with which file.
struct IoStatus {
  IoError error = IoError::none;
  std::string message;  // empty when ok; else a sentence naming the file

  bool ok() const noexcept { return error == IoError::none; }
  explicit operator bool() const noexcept { return ok(); }
};

enum class FileFormat : std::uint8_t { unknown, png, pfm, exr };
const char* to_string(FileFormat format) noexcept;
// The format named by the extension of `path`, case-insensitive: .png, .pfm, .exr; else unknown.
FileFormat format_from_path(const std::string& path);

// A decoded image: planar float planes with the stored values.
struct LoadedImage {
  Image image;        // 1 plane grey, 2 grey + alpha, 3 RGB, 4 RGBA (read_depth: the one plane)
  int bit_depth = 0;  // PNG 8 or 16 (values in 0 .. 2^bit_depth - 1); PFM 32; EXR 16 when every
                      // channel read is half, else 32
  FileFormat format = FileFormat::unknown;
  // EXR only (read_exr, read_image): the depth channel when the file has one, else empty.
  Image depth;
  std::string color_layer;    // EXR: the layer prefix of the colour channels read ("" top level)
  std::string depth_channel;  // EXR: the full name of the channel read as depth ("" none)
};

// What a file's header says, read without decoding a pixel (read_image_info, read_depth_info).
// Every check that needs no pixel is made here too (size limits, a file too short for its size, a
// channel layout read_image or read_depth would refuse), so that a command can check all of its
// inputs against each other before it decodes, and allocates, anything.
struct ImageInfo {
  int width = 0;
  int height = 0;
  int channels = 0;  // as read_image / read_depth would return them
  FileFormat format = FileFormat::unknown;
  // Of the channels read_image_info (read_depth_info) would return: PNG 8 or 16; PFM 32; EXR 16
  // when each of them is half, else 32 (a depth channel beside the colour does not count).
  int bit_depth = 0;
};

// ---- PNG ----

// Reads a PNG file: 8- and 16-bit grey, grey + alpha, RGB and RGBA as stored. Other forms are
// expanded by libpng to one of these: palette to RGB (RGBA if it has a transparency chunk),
// 1/2/4-bit grey to 8 bits (scaled to 0..255), a tRNS colour key to an alpha plane.
// Interlaced files are de-interlaced. Ancillary data (gamma, colour profile, text) is ignored.
// On failure `*out` is left empty.
IoStatus read_png(const std::string& path, LoadedImage* out);

// Writes `color` as an 8- or 16-bit PNG: 1 channel grey, 2 grey + alpha, 3 RGB, 4 RGBA (planar or
// interleaved RGBA). Values are rounded to the nearest integer and clamped to
// 0 .. 2^bit_depth - 1; NaN is written as 0. An existing file at `path` is replaced.
IoStatus write_png(const std::string& path, const ColorView& color, int bit_depth = 8);

// ---- PFM (portable float map) ----
//
// "PF" (3 channels, RGB) or "Pf" (1 channel), then width and height, then a scale whose sign
// gives the byte order of the 32-bit IEEE floats (negative: little-endian, positive: big-endian)
// and whose magnitude is ignored; one whitespace byte, then the rows from the *bottom* of the
// image to the top. Values are stored and read back bit for bit (NaN and infinities included).

enum class ByteOrder : std::uint8_t { little, big };

// On failure `*out` is left empty. Data after the last row is ignored.
IoStatus read_pfm(const std::string& path, LoadedImage* out);
// `color` must have 1 or 3 channels (planar); 2 or 4 are refused rather than silently dropping
// alpha: pass a view of the first 3 planes to drop it.
IoStatus write_pfm(const std::string& path, const ColorView& color, ByteOrder order = ByteOrder::little);

// ---- OpenEXR ----
//
// Reading: single-part scanline or tiled files (the first part of a multi-part file); deep data
// is refused. Every channel read is converted to float; the image is the data window (the display
// window is ignored). Channels with x/y subsampling are refused.
//
// Which channels are read (names are case-sensitive unless said otherwise; a "layer" is the
// prefix before the last '.'):
//  * Colour: the top-level R, G, B (and A if present); else the one layer L with L.R, L.G, L.B
//    (and L.A), preferring, among several, the single one whose last component is "Combined"
//    (Blender's beauty pass, "ViewLayer.Combined.R"); else the top-level Y (and A): grey.
//    Several candidate layers and no single "Combined" one is an error (name one in the options).
//  * Depth: the top-level Z; else a top-level channel named "depth" in any case; else a channel
//    whose last component is Z or "depth" (any case) in a layer whose last component is "Depth"
//    (any case), e.g. Blender's "ViewLayer.Depth.Z"; else the only other channel whose last
//    component is Z or "depth" (e.g. "render.Z"). In the last two steps a layer that also has an
//    X or Y channel (a vector pass: Blender's Normal, Vector, Position) or whose last component is
//    "Mist" (Blender's mist pass keeps a 0..1 fog factor in Z) is never taken. More than one
//    candidate at the step that decides is an error (name one in the options).
struct ExrReadOptions {
  std::optional<std::string> color_layer;    // unset: the rule above; "" top-level R,G,B; "L": L.R, L.G, L.B
  std::optional<std::string> depth_channel;  // unset: the rule above; "": read no depth; else a full channel name
};

enum class ExrPixelType : std::uint8_t { half, float32 };

struct ExrWriteOptions {
  ExrPixelType color_type = ExrPixelType::float32;  // half rounds to nearest; beyond +-65504 is inf
  ExrPixelType depth_type = ExrPixelType::float32;
  std::string color_layer;          // "": channels R, G, B, A (Y, A for grey); "L": L.R, L.G, ...
  std::string depth_channel = "Z";  // full name, e.g. "ViewLayer.Depth.Z"
};

// On failure `*out` is left empty. Succeeds when the file has colour or depth (or both): a file
// with neither is an unsupported channel layout.
IoStatus read_exr(const std::string& path, LoadedImage* out, const ExrReadOptions& options = {});
// Writes `color` (1 Y, 2 Y A, 3 R G B or 4 R G B A channels; or none: channels == 0) and, when
// `depth` is not null, the depth plane, which must have the colour's size. ZIP compression
// (lossless). At least one of colour and depth must be given.
IoStatus write_exr(const std::string& path, const ColorView& color, const FloatPlane* depth = nullptr,
                   const ExrWriteOptions& options = {});

// ---- By extension ----

// The header of what read_image (read_depth) would read; the same errors, without the pixels.
IoStatus read_image_info(const std::string& path, ImageInfo* out);
IoStatus read_depth_info(const std::string& path, ImageInfo* out);

struct WriteOptions {
  int png_bit_depth = 0;  // 8 or 16; 0: 8 for write_image, 16 for write_depth
  ByteOrder pfm_byte_order = ByteOrder::little;
  ExrWriteOptions exr;
};

// The colour image of a .png, .pfm or .exr file (read_png, read_pfm, read_exr). An EXR's depth
// channel, when present, comes along in `out->depth`; an EXR without colour channels is an error
// (read it with read_depth). Any other extension is an error (not_this_format).
IoStatus read_image(const std::string& path, LoadedImage* out);
IoStatus write_image(const std::string& path, const ColorView& color, const WriteOptions& options = {});

// A single-channel depth or disparity image, as stored, in `out->image` (one plane):
//  * PNG: 8- or 16-bit grey (the stored integers; e.g. Middlebury disparity PNGs hold 4 x the
//    disparity: scale as the data set says);
//  * PFM: "Pf";
//  * EXR: the depth channel of the rule above; a file without one but with exactly one channel
//    (whatever its name) gives that channel.
// Anything else (an RGB PNG or PFM, several EXR channels and none named as depth) is an
// unsupported channel layout.
IoStatus read_depth(const std::string& path, LoadedImage* out);
// PNG: grey, quantised like write_png (16-bit unless options say 8); PFM: "Pf"; EXR: one channel
// named options.exr.depth_channel of type options.exr.depth_type.
IoStatus write_depth(const std::string& path, const FloatPlane& depth, const WriteOptions& options = {});

// ---- Packed colour: an engine's RGBA buffer ----
//
// Colour as an engine holds it (reproject::ColorFormat): interleaved R, G, B, A pixels, one byte
// per channel (rgba8, rgba8_srgb) or one IEEE half (rgba16f, the machine's byte order), rows
// tightly packed. The values are the file's, bit for bit: no scaling, no colour management. A
// file with fewer channels is expanded on reading (grey to R = G = B; a missing alpha opaque:
// 255, or half 1.0) and `channels` says how many it had, so that the result can be written back
// in the same layout.
struct PackedColor {
  std::vector<std::uint8_t> bytes;  // height rows of width * bytes_per_pixel(format) bytes
  int width = 0;
  int height = 0;
  int channels = 0;  // of the file: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA
  ColorFormat format = ColorFormat::rgba8;

  std::ptrdiff_t stride() const noexcept { return static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(format); }
  ColorView view() const noexcept { return ColorView::packed(format, bytes.data(), width, height, stride()); }
  MutableColorView mutable_view() noexcept { return MutableColorView::packed(format, bytes.data(), width, height, stride()); }
};

// An 8-bit PNG (any colour type read_png takes) as rgba8 bytes labelled `format` (rgba8 or
// rgba8_srgb: the bytes are the same, the label says how they are blended). A 16-bit PNG is
// unsupported. On failure `*out` is left empty.
IoStatus read_png_packed(const std::string& path, ColorFormat format, PackedColor* out);
// Writes the first `channels` of an rgba8 / rgba8_srgb view as an 8-bit PNG: 1 grey (R), 2 grey
// + alpha (R, A), 3 RGB, 4 RGBA.
IoStatus write_png_packed(const std::string& path, const ColorView& packed, int channels);
// An EXR's colour channels (the rule above) as rgba16f, read without widening to float: each
// must be half (else unsupported). Y is repeated into R, G and B.
IoStatus read_exr_packed(const std::string& path, PackedColor* out);
// Writes the first `channels` of an rgba16f view as half channels (1 Y, 2 Y A, 3 R G B, 4 R G B
// A; Y is R), named as write_exr names them; ZIP compression.
IoStatus write_exr_packed(const std::string& path, const ColorView& packed, int channels,
                          const ExrWriteOptions& options = {});

// ---- Raw buffers ----
//
// A buffer's bytes with no header: the tool's engine dumps (docs/CLI.md). Rows are tightly
// packed; words of `word_bytes` (1, 2 or 4) are little-endian in the file and in the machine's
// byte order in memory.

// Header phase: `path` is a regular file of exactly `bytes` bytes; otherwise size_mismatch, with
// a message naming the file, its size and `what` ("a 960x540 unorm16 buffer (2 bytes per pixel)").
IoStatus check_raw_size(const std::string& path, std::uint64_t bytes, const std::string& what);
// The whole file, which must be `bytes` long (as check_raw_size). On failure `*out` is empty.
IoStatus read_raw(const std::string& path, std::uint64_t bytes, int word_bytes, const std::string& what,
                  std::vector<std::uint8_t>* out);
// `height` rows of `row_bytes` bytes, row y at data + y * stride.
IoStatus write_raw(const std::string& path, const std::uint8_t* data, std::size_t row_bytes, int height,
                   std::ptrdiff_t stride, int word_bytes);

// ---- Temporary files ----
//
// Every temporary file the writers create (and any a caller registers, e.g. the tool's staged
// outputs) is tracked until it is renamed into place or deleted, so that a signal handler can
// remove them: remove_temporary_files() is async-signal-safe. It unlinks every tracked file, then
// removes every tracked directory that is empty, newest first.
void track_temporary(const std::string& path);
void untrack_temporary(const std::string& path);
void remove_temporary_files() noexcept;
// Creates `path` for writing, failing if it exists (`*exists` then set; `*error` says why), tracked
// from before it exists. On Windows remove_temporary_files() may run on another thread (the
// console's control handler) while the program goes on: from then on nothing is created, and a
// creation under way finishes first, so that no file appears after the clean-up.
std::FILE* create_temporary(const std::string& path, bool* exists, std::string* error);

}  // namespace reproject::io
