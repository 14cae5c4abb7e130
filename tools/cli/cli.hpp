// The `reproject` command-line tool: shared pieces of its subcommands (docs/CLI.md is the
// user's reference; this header is the code's).
//
// Errors. Every subcommand reports a failure by throwing Failure; main() prints its message as one
// line on stderr ("reproject: error: ...") and exits with its code. Exceptions stay inside the
// tool: the library never throws, and nothing here calls the library from a destructor.
#pragma once

#include <cstdint>
#include <atomic>
#include <string>
#include <vector>

#include "imageio/imageio.hpp"
#include "reproject/reproject.hpp"

namespace reproject::cli {

// Exit codes (docs/CLI.md).
enum ExitCode : int {
  kExitOk = 0,
  kExitRuntime = 1,  // the library refused the call, or allocation failed
  kExitUsage = 2,    // unknown subcommand or flag, missing or bad value, conflicting flags
  kExitInput = 3,    // an input file is missing, unreadable, of the wrong format, or of the wrong size
  kExitOutput = 4,   // an output file or directory cannot be written
  kExitInterrupted = 130,  // Windows: Ctrl-C, Ctrl-Break or the console closing stopped the command
};

struct Failure {
  int code;
  std::string message;
};
[[noreturn]] void fail(int code, const std::string& message);
// Whether `text` is a plain decimal number: an optional sign, digits, and unless `integer_only` a
// fraction and an exponent. No blanks, no hexadecimal, no "inf" or "nan".
bool is_decimal(const std::string& text, bool integer_only);

// ---- Flags ----------------------------------------------------------------------------------

// One subcommand's flags: "--name value", "--name=value", or a bare "--name" for switches.
// Parsing checks the names (unknown: usage error), that values are present and that no flag is
// given twice; the typed getters check the values.
class Flags {
 public:
  struct Spec {
    const char* name;     // without the leading "--"
    const char* metavar;  // nullptr: a switch that takes no value
    const char* help;
  };

  Flags(const char* command, std::vector<Spec> specs) : command_(command), specs_(std::move(specs)) {}
  // Parses argv[first..argc). "--help" / "-h" sets help().
  void parse(int argc, char** argv, int first);
  bool help() const noexcept { return help_; }
  // The usage text: a synopsis line followed by one line per flag.
  std::string usage(const char* synopsis) const;

  bool has(const char* name) const;
  const char* command() const noexcept { return command_; }

  std::string text(const char* name, const std::string& fallback = "") const;
  int integer(const char* name, int fallback, int min, int max) const;
  double number(const char* name, double fallback) const;  // any finite value
  // A finite value in [min, max] (min_open: excluding min).
  double number(const char* name, double fallback, double min, double max, bool min_open = false) const;
  // Comma-separated list, empty items refused.
  std::vector<std::string> list(const char* name, const std::string& fallback) const;
  // A usage error about this flag's value: "--name: <what>".
  [[noreturn]] void bad_value(const char* name, const std::string& what) const;
  // Refuses the presence of `name` (usage error: "--name cannot be used with <why>").
  void forbid(const char* name, const std::string& why) const;
  // Requires `name`: "<command> needs --name <metavar>".
  void require(const char* name) const;

 private:
  const Spec* find(const std::string& name) const;
  const char* command_;
  std::vector<Spec> specs_;
  std::vector<std::pair<std::string, std::string>> values_;
  bool help_ = false;
};

// ---- Files ----------------------------------------------------------------------------------

// Colour as the tool carries it: normalised to 0..1 (PNG integers divided by 2^bits - 1; PFM and
// EXR floats as stored), so that PSNR and pictures mean the same whatever the file held.
struct ColorImage {
  Image image;
  int bit_depth = 8;  // of the file it came from: 8, 16 (PNG, or half EXR) or 32 (float)
  io::FileFormat format = io::FileFormat::png;
};

// Inputs. Every command reads the headers of all its inputs first (color_info, depth_info) and
// checks them against each other, so that a wrong size or layout fails before a pixel is decoded
// or a large buffer allocated; then it decodes (read_color, read_depth_file). Any failure is a
// Failure with imageio's message, which names the file: kExitRuntime when memory ran out, else
// kExitInput.
io::ImageInfo color_info(const std::string& path);
io::ImageInfo depth_info(const std::string& path);
ColorImage read_color(const std::string& path);
// A single-channel depth or disparity file as stored (PNG integers, PFM/EXR floats).
io::LoadedImage read_depth_file(const std::string& path);
// "WxH" for messages.
std::string size_text(int width, int height);

// Checks, before any work, that `path`'s extension names a format the tool writes (usage error).
void check_output_path(const char* flag, const std::string& path);
// Checks, before any work, that the given output flags name different files (usage error).
void check_distinct_outputs(const Flags& flags, const std::vector<const char*>& names);
// Whether two paths name one existing file (same device and inode: "./x", a symlink, a hard link).
bool same_file(const std::string& a, const std::string& b);
// Whether two paths name one destination: same_file, or the same path once resolved.
bool same_destination(const std::string& a, const std::string& b);

// Every file one command writes, written all or nothing:
//  * before any work, input() names each input file and expect() each output file: an output that
//    is an input (under any spelling) is a usage error; a directory in its place, or a directory
//    it cannot be created in, is kExitOutput. expect() reserves the output's temporary file
//    (<name>.reproject-tmp<pid>-<n>.<ext>, next to it); make_directory() creates directories now;
//  * the writers (color, plane, ...) write into those temporary files;
//  * commit() renames them all into place once every one is written; should a rename fail, the
//    ones before it are undone, so every destination holds its previous file again. A replaced
//    file keeps its mode.
// If the command fails first, the destructor removes the temporary files, and the directories it
// created when they are left empty; remove_temporaries_on_signals() does the same when SIGINT,
// SIGTERM, SIGHUP or SIGQUIT ends the process (Windows: Ctrl-C, Ctrl-Break, the console closing).
class OutputSet {
 public:
  OutputSet() = default;
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  void input(const std::string& flag, const std::string& path);
  void expect(const std::string& flag, const std::string& path);
  // input() / expect() for each of these flags that is given.
  void inputs(const Flags& flags, const std::vector<const char*>& names);
  void outputs(const Flags& flags, const std::vector<const char*>& names);
  // Creates `dir` (and its parents) if missing; kExitOutput on failure.
  void make_directory(const std::string& dir);
  // Colour normalised 0..1: PNG 8 or 16 bits (scaled by 2^bits - 1), PFM/EXR floats (EXR half
  // when `exr_half`). PFM keeps 1 or 3 channels (grey + alpha and RGBA lose alpha).
  void color(const std::string& path, const ColorView& color, int png_bits = 8, bool exr_half = false);
  // Packed colour (ColorView::packed) as it is, in the file type of `path`: rgba8 / rgba8_srgb as
  // an 8-bit .png, rgba16f as a half .exr (the first `channels` channels), any format as .raw
  // (all four, the bytes).
  void packed_color(const std::string& path, const ColorView& packed, int channels);
  // A buffer's bytes as a .raw file: `height` rows of `row_bytes`, row y at data + y * stride;
  // words of `word_bytes` written little-endian.
  void raw(const std::string& path, const std::uint8_t* data, std::size_t row_bytes, int height, std::ptrdiff_t stride,
           int word_bytes);
  // Values as they are (depth, source x): PNG 16-bit integers, PFM/EXR floats.
  void plane(const std::string& path, const FloatPlane& plane, int png_bits = 16);
  // A picture of 0..255 floats (stereo_views) as an 8-bit PNG, values as they are.
  void picture(const std::string& path, const Image& picture);
  // Bytes as an 8-bit grey PNG (status: 0 hit, 1 hole, 2 outside, 3 clipped; masks).
  void bytes(const std::string& path, const std::uint8_t* data, int width, int height);
  // Any text (JSON).
  void text(const std::string& path, const std::string& content);
  void commit();

 private:
  static std::string sibling(const std::string& path, const char* what, std::size_t n);
  void raw_to(const std::string& path, const std::string& temporary, const std::uint8_t* data, std::size_t row_bytes,
              int height, std::ptrdiff_t stride, int word_bytes);
  const std::string& stage(const std::string& path);
  void check(const io::IoStatus& status, const std::string& path, const std::string& temporary);
  struct Staged {
    std::string temporary, destination;
    bool written = false;
  };
  std::vector<std::pair<std::string, std::string>> inputs_;  // flag, path
  std::vector<Staged> staged_;
  std::vector<std::string> created_dirs_;
  bool committed_ = false;
};
// Installs the handlers that remove every temporary file when a signal ends the process (main).
// POSIX: SIGINT, SIGTERM, SIGHUP, SIGQUIT remove them and end the process. Windows: a console
// control event (Ctrl-C, Ctrl-Break, the console closing, logoff, shutdown) sets interruption(),
// which every library call of the tool reads as Options::cancel: the call stops within a block of
// rows, the command fails with kExitInterrupted, and its OutputSet removes its files as on any
// failure; a command that does not get there within 3 s is ended by the handler, which removes
// the temporary files itself.
void remove_temporaries_on_signals();
// The flag a console control event sets (never set on POSIX, where a signal ends the process).
const std::atomic<bool>* interruption();
// kExitInterrupted if interruption() is set.
void fail_if_interrupted();

// ---- Source frames, depth decoding and the parallax model --------------------------------------

// Flags every reprojecting subcommand shares (appended to its own).
std::vector<Flags::Spec> source_flags();  // --color --depth --encoding --near --far --depth-scale --unknown-depth
std::vector<Flags::Spec> camera_flags(bool with_direction, bool with_disparity);
// warp's and pair's other ways to the parallax: a renderer's rig (--interaxial, --fov) instead of
// --separation, and relative inverse depth (--relative-depth, --max-parallax, --zero-plane).
std::vector<Flags::Spec> rig_flags();
std::vector<Flags::Spec> option_flags(bool with_method, bool with_guard, bool with_threads_arch);

// A source depth buffer in an engine's format, read from a .raw file (--depth-format).
struct RawDepth {
  std::vector<std::uint8_t> bytes;  // empty: none (the depth is Frame::depth)
  DepthFormat format = DepthFormat::float32;
  int width = 0;
  int height = 0;
  float linear_near = 0.0f;  // rgba8_packed_linear: --linear-range
  float linear_far = 1.0f;

  std::ptrdiff_t stride() const noexcept { return static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(format); }
  DepthBuffer view() const noexcept;
  MutableDepthBuffer mutable_view() noexcept;  // an output buffer
};

struct Frame {
  ColorImage color;
  Image depth;             // stored values x depth scale, unknown values filled
  int depth_bits = 32;     // of the depth file: 8/16 (PNG integers), 16/32 (EXR half/float), 32 (PFM)
  double depth_scale = 1;  // K: depth = file value x K
  long unknown_filled = 0;
  // warp and pair (load_source): the colour read natively in an engine format (then `color` is
  // empty), and the depth as a raw buffer (then `depth` is empty).
  io::PackedColor packed_color;
  bool color_from_raw = false;
  RawDepth raw_depth;

  bool native_color() const noexcept { return !packed_color.bytes.empty(); }
  bool native_depth() const noexcept { return !raw_depth.bytes.empty(); }
  int width() const noexcept { return native_depth() ? raw_depth.width : depth.width(); }
  int height() const noexcept { return native_depth() ? raw_depth.height : depth.height(); }
  int color_channels() const noexcept { return native_color() ? packed_color.channels : color.image.channels(); }
  // The source views reproject() takes.
  ColorView color_view() const noexcept;
  SourceView source() const noexcept;
};
// The headers of --color and --depth, checked against each other; the colour's is returned.
io::ImageInfo frame_info(const Flags& flags);
// Reads --color and --depth (after frame_info), applies --depth-scale and --unknown-depth.
Frame load_frame(const Flags& flags, const DepthDecoder& decoder);
// The depth half of load_frame: --depth with --depth-scale and --unknown-depth applied.
struct DepthFile {
  Image depth;
  int bits = 32;
  double scale = 1;
  long unknown_filled = 0;
};
DepthFile load_depth(const Flags& flags, const DepthDecoder& decoder);
// Replaces every pixel with `unknown` set by the farther (smaller inverse depth) of its nearest
// known neighbours in the row; a row with no known pixel gets the farthest value the encoding has
// (the far plane; infinity for linear and the infinite encodings; 0 for disparity). Returns the
// number of pixels filled.
long fill_unknown_depth(Image* depth, const std::vector<std::uint8_t>& unknown, const DepthDecoder& decoder);

// ---- Engine-native formats and raw dumps (warp, pair; docs/CLI.md "Native formats") ----------

// --color-space --float-color --size --color-format --depth-format --linear-range
std::vector<Flags::Spec> native_flags();
// What those flags say, checked against each other and against the file names before any file
// is read.
struct NativeSpec {
  ColorFormat png_format = ColorFormat::rgba8;  // --color-space: how 8-bit PNG colour blends natively
  bool float_color = false;                          // --float-color: never read colour natively
  bool raw_color = false;                            // --color is a .raw file ...
  ColorFormat color_format = ColorFormat::rgba8;     // ... of this format (--color-format)
  bool raw_depth = false;                            // --depth is a .raw file ...
  DepthFormat depth_format = DepthFormat::float32;   // ... of this format (--depth-format)
  int width = 0, height = 0;                         // --size, for the .raw files
  float linear_near = 0.0f, linear_far = 1.0f;       // --linear-range (rgba8_packed_linear)
};
NativeSpec native_spec_from_flags(const Flags& flags);
// Whether `path` names a raw buffer (.raw, case-insensitive).
bool is_raw_path(const std::string& path);
// Checks, before any work, a colour output (--out, --out-left, ...) and a depth output
// (--out-depth, ...) against the source: a .raw colour is written as .raw or in its own file type,
// a .raw depth as .raw, .pfm or .exr; .raw outputs need .raw inputs (usage errors).
void check_color_output(const char* flag, const std::string& path, const NativeSpec& spec);
void check_depth_output(const char* flag, const std::string& path, const NativeSpec& spec);
// load_frame for warp and pair: reads --color natively (an 8-bit PNG as rgba8 / rgba8_srgb, a half
// EXR as rgba16f) when nothing in `color_outputs` needs another file type and --float-color is
// not given, or as a .raw buffer; --depth as a .raw buffer or as load_depth does. Headers (and raw
// files' sizes) are checked against each other first.
Frame load_source(const Flags& flags, const NativeSpec& spec, const DepthDecoder& decoder,
                  const std::vector<std::string>& color_outputs);
// "colour rgba8_srgb (native), depth unorm16 (raw)" for the summary line.
std::string formats_text(const Frame& frame);
// The size of the words whose byte order a .raw file fixes (little-endian): 1, 2 or 4.
int raw_word_bytes(DepthFormat format);
int raw_word_bytes(ColorFormat format);
// A raw depth buffer's stored values d as floats (the value the decoder decodes), for .pfm / .exr.
Image stored_depth_values(const RawDepth& depth);
// Packed colour (`channels` of the file it came from) as 0..1 floats, for the stereo pictures.
Image float_color_of(const ColorView& packed, int channels);

DepthDecoder decoder_from_flags(const Flags& flags);
// The model for a source `width` target pixels wide (guard band excluded), and the direction.
ParallaxModel model_from_flags(const Flags& flags, int width, EyeDirection* direction);
// Options from the option flags; --threads and --arch only when `read_threads_arch`.
Options options_from_flags(const Flags& flags, bool read_threads_arch);
// --dilate-depth (0..4096) [0].
int dilate_radius_from_flags(const Flags& flags);
// The halo pre-filter (dilate_nearer_depth): each depth becomes the nearest one within `radius`
// columns of its row; nothing when radius is 0. Runs on stored values after --depth-scale.
void dilate_depth(Image* depth, const DepthDecoder& decoder, int radius);
// REPROJECT_FORCE_ARCH, when set, must name an instruction set, and REPROJECT_SRGB_LOOKUP
// `gathers` or `permutes` (the library would only warn on stderr and ignore them): a usage error
// naming the valid values. An unsupported set stays allowed: the library then falls back to the
// best supported set, as documented.
void check_environment();
// --arch, checked against this CPU; selected_arch() when absent.
Arch arch_from_flags(const Flags& flags);
// Every instruction set the library names, in its order, "scalar, sse, avx2, avx512" (with
// `last_separator` before the last one), for help texts and messages.
std::string arch_names(const char* last_separator = ", ");
// kExitRuntime with the library's message.
void check_status(const Status& status, const std::string& what);

// ---- Pictures ---------------------------------------------------------------------------------

// Pictures follow imageio/stereo_views.hpp: 0..255 floats, written as 8-bit PNG as they are
// (OutputSet::picture). These helpers add what the tool needs on top of stereo_views.

// A copy of normalised colour (0..1) scaled to 0..255, for stereo_views.
Image to_picture_scale(const ColorView& color);
// Fails with kExitRuntime if `status` is not ok (stereo_views only fails on bad arguments or
// memory).
void check_picture(const io::IoStatus& status, const char* what);
// Paints the pixels whose mask byte is 0 in a dim blue, so that a heat map shows which pixels
// were not measured (not visible in both views).
void mark_unmeasured(Image* picture, const std::uint8_t* mask);
// The region [x0, x0 + w) x [y0, y0 + h) of `image`, clamped to it; 3 channels (grey repeated).
Image crop(const Image& image, int x0, int y0, int w, int h);
// Box-filter downscale by an integer factor (>= 1).
Image downscale(const Image& image, int factor);
// Tiles in a grid of `columns`, each cell as large as the largest tile, `gap` pixels apart on a
// dark background; 3 channels.
Image mosaic(const std::vector<const Image*>& tiles, int columns, int gap);
// Writes `text` (letters, digits, space and . , : % / - + = ~ ( ) |) at (x, y) in white on a dark
// box, `scale` image pixels per font pixel; 3-channel pictures.
void label(Image* image, int x, int y, const std::string& text, int scale);

// ---- Subcommands ------------------------------------------------------------------------------

int run_warp(int argc, char** argv);
int run_pair(int argc, char** argv);
int run_compare(int argc, char** argv);
int run_scene(int argc, char** argv);
int run_budget(int argc, char** argv);

}  // namespace reproject::cli
