// Image formats and stereo views of tools/imageio (reproject_format_tests).
//
// Suite Pfm: round trips of 1- and 3-channel files in both byte orders, bit for bit; the file layout
//   (header, byte order, bottom-to-top rows) checked against bytes built by hand; bad files.
// Suite Png: 8- and 16-bit colour and 16-bit depth through the generic front end.
// Suite Exr: float and half RGBA + Z, grey, depth-only; files written with the OpenEXR API directly
//   for what our writer does not produce: Blender-style layer names with other passes beside the
//   depth, a lower-case "depth", a data window away from the origin, a tiled file, ambiguous
//   layers; bad files.
// Suites Packed and Raw: 8-bit PNG and half EXR colour as RGBA8 / RGBA16F bytes, every channel
//   count, and raw buffers (little-endian words, rows packed, exact sizes).
// Suite Formats: format detection by extension and the generic read/write/depth calls, with their
//   errors (unknown extension, content not matching the extension, size mismatches).
// Suite TemporaryFiles: a writer killed by a signal at random moments leaves no temporary file.
// Suite StereoViews: exact pixels of every packing, both anaglyphs, the status colours and the
//   heat map on small synthetic inputs.
#include <gtest/gtest.h>

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfTileDescription.h>
#include <ImfTiledOutputFile.h>
#include <half.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#if defined(_WIN32)
#include "support/windows_process.hpp"
#else
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

#include "imageio/imageio.hpp"
#include "imageio/os.hpp"
#include "imageio/stereo_views.hpp"
#include "reproject/image.hpp"
#include "support/files.hpp"

namespace {

using reproject::ColorLayout;
using reproject::ColorView;
using reproject::FloatPlane;
using reproject::Image;
namespace io = reproject::io;

// ------------------------------------------------------------------------------------------------
// Helpers

// A path in the test temp directory no other test (or concurrent run) uses.
std::string temp_path(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto ticks = std::chrono::steady_clock::now().time_since_epoch().count();
  return ::testing::TempDir() + "reproject_formats_" + info->test_suite_name() + "_" + info->name() + "_" +
         std::to_string(ticks) + "_" + tag;
}

// Removes the file when the test ends, passed or not.
struct TempFile {
  explicit TempFile(const std::string& tag) : path(temp_path(tag)) {}
  ~TempFile() {
    std::error_code error;
    std::filesystem::remove(path, error);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  std::string path;
};

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void write_text(const std::string& path, const std::string& text) {
  write_bytes(path, std::vector<unsigned char>(text.begin(), text.end()));
}

std::uint32_t bits_of(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

float& at(Image& image, int c, int x, int y) { return image.mutable_plane(c).row(y)[x]; }
float at(const Image& image, int c, int x, int y) { return image.plane(c).row(y)[x]; }

// Fills every plane with f(c, x, y).
template <class F>
Image make_image(int width, int height, int channels, F f) {
  Image image(width, height, channels);
  for (int c = 0; c < channels; ++c) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) at(image, c, x, y) = f(c, x, y);
    }
  }
  return image;
}

// Values that exercise a float format: negative, large, small, subnormal, signed zero.
float float_value(int c, int x, int y) {
  static const float kSpecial[] = {-1.5f, 3.0e38f, -3.0e38f, 1.0e-30f, 1.0e-42f /* subnormal */, -0.0f,
                                   123456.789f, 0.1f};
  const int i = (x + 3 * y + 5 * c) % 11;
  if (i < 8) return kSpecial[i];
  return static_cast<float>(x * 0.25 - y * 17.5 + c * 1000.0);
}

// Bit-for-bit equality of two images' planes.
void expect_same_bits(const Image& expected, const Image& actual) {
  ASSERT_EQ(actual.width(), expected.width());
  ASSERT_EQ(actual.height(), expected.height());
  ASSERT_EQ(actual.channels(), expected.channels());
  for (int c = 0; c < expected.channels(); ++c) {
    for (int y = 0; y < expected.height(); ++y) {
      for (int x = 0; x < expected.width(); ++x) {
        ASSERT_EQ(bits_of(at(actual, c, x, y)), bits_of(at(expected, c, x, y)))
            << "c " << c << " x " << x << " y " << y << ": " << at(actual, c, x, y) << " vs " << at(expected, c, x, y);
      }
    }
  }
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ------------------------------------------------------------------------------------------------
// Pfm

TEST(Pfm, RoundTripThreeChannelsBothByteOrders) {
  const Image image = make_image(7, 5, 3, float_value);
  for (io::ByteOrder order : {io::ByteOrder::little, io::ByteOrder::big}) {
    TempFile file("rgb.pfm");
    const io::IoStatus written = io::write_pfm(file.path, image.color(), order);
    ASSERT_TRUE(written.ok()) << written.message;
    io::LoadedImage loaded;
    const io::IoStatus read = io::read_pfm(file.path, &loaded);
    ASSERT_TRUE(read.ok()) << read.message;
    EXPECT_EQ(loaded.format, io::FileFormat::pfm);
    EXPECT_EQ(loaded.bit_depth, 32);
    expect_same_bits(image, loaded.image);
    EXPECT_EQ(rptest::leftovers(file.path), 0);
  }
}

TEST(Pfm, RoundTripOneChannelFromAStridedView) {
  // A view of every other float of a wider buffer: the writer must honour the stride.
  const Image wide = make_image(12, 4, 1, float_value);
  FloatPlane plane = wide.plane(0);
  plane.width = 5;
  const Image expected = make_image(5, 4, 1, float_value);
  TempFile file("grey.pfm");
  ASSERT_TRUE(io::write_pfm(file.path, ColorView::planar({plane}), io::ByteOrder::big).ok());
  io::LoadedImage loaded;
  ASSERT_TRUE(io::read_pfm(file.path, &loaded).ok());
  expect_same_bits(expected, loaded.image);
}

TEST(Pfm, FileLayoutIsHeaderThenRowsBottomToTop) {
  // 2x2 grey: top row (1, 2), bottom row (3, 4).
  Image image(2, 2, 1);
  at(image, 0, 0, 0) = 1.0f;
  at(image, 0, 1, 0) = 2.0f;
  at(image, 0, 0, 1) = 3.0f;
  at(image, 0, 1, 1) = 4.0f;
  const std::string header_le = "Pf\n2 2\n-1.0\n";
  const std::string header_be = "Pf\n2 2\n1.0\n";
  // 3.0f = 0x40400000, 4.0f = 0x40800000, 1.0f = 0x3F800000, 2.0f = 0x40000000.
  const std::vector<unsigned char> data_le = {0, 0, 0x40, 0x40, 0, 0, 0x80, 0x40, 0, 0, 0x80, 0x3F, 0, 0, 0, 0x40};
  const std::vector<unsigned char> data_be = {0x40, 0x40, 0, 0, 0x40, 0x80, 0, 0, 0x3F, 0x80, 0, 0, 0x40, 0, 0, 0};

  TempFile le("le.pfm");
  TempFile be("be.pfm");
  ASSERT_TRUE(io::write_pfm(le.path, image.color(), io::ByteOrder::little).ok());
  ASSERT_TRUE(io::write_pfm(be.path, image.color(), io::ByteOrder::big).ok());
  std::vector<unsigned char> expected_le(header_le.begin(), header_le.end());
  expected_le.insert(expected_le.end(), data_le.begin(), data_le.end());
  std::vector<unsigned char> expected_be(header_be.begin(), header_be.end());
  expected_be.insert(expected_be.end(), data_be.begin(), data_be.end());
  EXPECT_EQ(file_bytes(le.path), expected_le);
  EXPECT_EQ(file_bytes(be.path), expected_be);

  // And a file another writer made: other whitespace, another scale magnitude, trailing bytes.
  TempFile other("other.pfm");
  std::vector<unsigned char> bytes;
  const std::string header = "Pf  2\t2\r\n-0.0039\n";
  bytes.assign(header.begin(), header.end());
  bytes.insert(bytes.end(), data_le.begin(), data_le.end());
  bytes.push_back('x');
  write_bytes(other.path, bytes);
  io::LoadedImage loaded;
  const io::IoStatus status = io::read_pfm(other.path, &loaded);
  ASSERT_TRUE(status.ok()) << status.message;
  expect_same_bits(image, loaded.image);
}

TEST(Pfm, BadFilesAreErrorsWithClearMessages) {
  io::LoadedImage loaded;
  TempFile file("bad.pfm");
  struct Case {
    std::string bytes;
    io::IoError error;
    const char* message;
  };
  const std::string pixels(3 * 2 * 2 * 4, '\0');
  const Case cases[] = {
      {"", io::IoError::not_this_format, "empty"},
      {"P6\n2 2\n255\n", io::IoError::not_this_format, "not a PFM file"},
      {"PFx\n2 2\n-1\n", io::IoError::not_this_format, "not a PFM file"},
      {"PF", io::IoError::truncated, "truncated"},
      {"PF\n2 2\n", io::IoError::truncated, "ends inside the PFM header (scale)"},
      {"PF\n0 2\n-1\n" + pixels, io::IoError::corrupt, "bad width"},
      {"PF\n2 -2\n-1\n" + pixels, io::IoError::corrupt, "bad height"},
      {"PF\n2 2\n0\n" + pixels, io::IoError::corrupt, "bad scale"},
      {"PF\n2 2\nnan\n" + pixels, io::IoError::corrupt, "bad scale"},
      {"PF\n2 2\n-1\n" + pixels.substr(0, 47), io::IoError::truncated, "47 of 48 bytes"},
      {"PF\n100000 100000\n-1\n", io::IoError::unsupported, "pixel limit"},
  };
  for (const Case& c : cases) {
    write_text(file.path, c.bytes);
    const io::IoStatus status = io::read_pfm(file.path, &loaded);
    EXPECT_EQ(status.error, c.error) << "file \"" << c.bytes.substr(0, 20) << "\": " << status.message;
    EXPECT_TRUE(contains(status.message, c.message)) << status.message;
    EXPECT_TRUE(contains(status.message, file.path)) << status.message;
    EXPECT_TRUE(loaded.image.empty());
  }

  const io::IoStatus missing = io::read_pfm(temp_path("missing.pfm"), &loaded);
  EXPECT_EQ(missing.error, io::IoError::open_failed) << missing.message;
  EXPECT_EQ(io::read_pfm(file.path, nullptr).error, io::IoError::invalid_argument);

  // PFM has no 2- or 4-channel form: refused, not silently cut.
  const Image rgba(3, 3, 4);
  TempFile out("rgba.pfm");
  const io::IoStatus refused = io::write_pfm(out.path, rgba.color());
  EXPECT_EQ(refused.error, io::IoError::unsupported) << refused.message;
  EXPECT_TRUE(contains(refused.message, "unsupported channel layout")) << refused.message;
  EXPECT_FALSE(std::filesystem::exists(out.path));
  EXPECT_EQ(rptest::leftovers(out.path), 0);
}

// ------------------------------------------------------------------------------------------------
// Png (the reader and writer have their own tests in test_teddy.cpp; here: through the front end)

TEST(Png, RoundTrip8And16BitColor) {
  for (int bits : {8, 16}) {
    const float top = bits == 8 ? 255.0f : 65535.0f;
    const Image image = make_image(9, 4, 3, [&](int c, int x, int y) {
      return std::fmod(static_cast<float>(x * 4099 + y * 257 + c * 31), top + 1.0f);
    });
    TempFile file("colour.png");
    io::WriteOptions options;
    options.png_bit_depth = bits;
    ASSERT_TRUE(io::write_image(file.path, image.color(), options).ok());
    io::LoadedImage loaded;
    const io::IoStatus status = io::read_image(file.path, &loaded);
    ASSERT_TRUE(status.ok()) << status.message;
    EXPECT_EQ(loaded.format, io::FileFormat::png);
    EXPECT_EQ(loaded.bit_depth, bits);
    expect_same_bits(image, loaded.image);
  }
}

TEST(Png, RoundTrip16BitDepth) {
  // 256 * k + k: both bytes differ, so a byte-order mistake shows.
  const Image depth = make_image(6, 5, 1, [](int, int x, int y) { return static_cast<float>(257 * (x + 6 * y) + 1); });
  TempFile file("depth.png");
  ASSERT_TRUE(io::write_depth(file.path, depth.plane(0)).ok());  // 16-bit by default
  io::LoadedImage loaded;
  const io::IoStatus status = io::read_depth(file.path, &loaded);
  ASSERT_TRUE(status.ok()) << status.message;
  EXPECT_EQ(loaded.bit_depth, 16);
  expect_same_bits(depth, loaded.image);

  // An RGB PNG is not a depth image.
  const Image rgb(2, 2, 3);
  TempFile color("colour.png");
  ASSERT_TRUE(io::write_image(color.path, rgb.color()).ok());
  const io::IoStatus refused = io::read_depth(color.path, &loaded);
  EXPECT_EQ(refused.error, io::IoError::unsupported) << refused.message;
  EXPECT_TRUE(contains(refused.message, "must have 1 channel, this one has 3")) << refused.message;
  EXPECT_TRUE(loaded.image.empty());
}

// ------------------------------------------------------------------------------------------------
// Packed: colour read and written as an engine's RGBA8 / RGBA16F bytes

// 8-bit PNGs of every channel count read as RGBA8 (grey repeated, missing alpha 255) and written
// back in their own layout, byte for byte.
TEST(Packed, PngOfEveryChannelCountRoundTrips) {
  for (int channels = 1; channels <= 4; ++channels) {
    SCOPED_TRACE(channels);
    const Image image = make_image(7, 3, channels, [](int c, int x, int y) { return static_cast<float>((x * 37 + y * 91 + c * 53) % 256); });
    TempFile file("in.png");
    ASSERT_TRUE(io::write_image(file.path, image.color()).ok());
    io::ImageInfo info;
    ASSERT_TRUE(io::read_image_info(file.path, &info).ok());
    EXPECT_EQ(info.bit_depth, 8);
    io::PackedColor packed;
    const io::IoStatus read = io::read_png_packed(file.path, reproject::ColorFormat::rgba8_srgb, &packed);
    ASSERT_TRUE(read.ok()) << read.message;
    EXPECT_EQ(packed.format, reproject::ColorFormat::rgba8_srgb);
    EXPECT_EQ(packed.channels, channels);
    ASSERT_EQ(packed.bytes.size(), 7u * 3u * 4u);
    for (int y = 0; y < 3; ++y) {
      for (int x = 0; x < 7; ++x) {
        const std::uint8_t* p = packed.bytes.data() + (y * 7 + x) * 4;
        const bool grey = channels <= 2;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(p[c], at(image, grey ? 0 : c, x, y)) << x << "," << y;
        EXPECT_EQ(p[3], channels == 2 ? at(image, 1, x, y) : channels == 4 ? at(image, 3, x, y) : 255.0f);
      }
    }
    TempFile out("out.png");
    ASSERT_TRUE(io::write_png_packed(out.path, packed.view(), channels).ok());
    io::LoadedImage back;
    ASSERT_TRUE(io::read_image(out.path, &back).ok());
    EXPECT_EQ(back.bit_depth, 8);
    expect_same_bits(image, back.image);
  }
}

TEST(Packed, SixteenBitPngAndFloatExrAreNotPacked) {
  const Image image = make_image(4, 2, 3, [](int c, int x, int) { return static_cast<float>(1000 * c + x); });
  TempFile png("c16.png");
  io::WriteOptions options;
  options.png_bit_depth = 16;
  ASSERT_TRUE(io::write_image(png.path, image.color(), options).ok());
  io::PackedColor packed;
  io::IoStatus status = io::read_png_packed(png.path, reproject::ColorFormat::rgba8, &packed);
  EXPECT_EQ(status.error, io::IoError::unsupported) << status.message;
  EXPECT_TRUE(packed.bytes.empty());
  TempFile exr("c32.exr");
  ASSERT_TRUE(io::write_exr(exr.path, image.color()).ok());
  io::ImageInfo info;
  ASSERT_TRUE(io::read_image_info(exr.path, &info).ok());
  EXPECT_EQ(info.bit_depth, 32);
  status = io::read_exr_packed(exr.path, &packed);
  EXPECT_EQ(status.error, io::IoError::unsupported) << status.message;
  EXPECT_TRUE(contains(status.message, "not all half")) << status.message;
  EXPECT_TRUE(packed.bytes.empty());
}

// Half EXRs of every channel count read as RGBA16F, the halves bit for bit (Y repeated, a
// missing alpha 1.0), and written back in their own layout.
TEST(Packed, HalfExrOfEveryChannelCountRoundTrips) {
  for (int channels = 1; channels <= 4; ++channels) {
    SCOPED_TRACE(channels);
    const Image image = make_image(5, 4, channels, [](int c, int x, int y) { return 0.1f * x - 0.37f * y + 2.5f * c; });
    io::ExrWriteOptions options;
    options.color_type = io::ExrPixelType::half;
    TempFile file("in.exr");
    ASSERT_TRUE(io::write_exr(file.path, image.color(), nullptr, options).ok());
    io::ImageInfo info;
    ASSERT_TRUE(io::read_image_info(file.path, &info).ok());
    EXPECT_EQ(info.bit_depth, 16);
    io::PackedColor packed;
    const io::IoStatus read = io::read_exr_packed(file.path, &packed);
    ASSERT_TRUE(read.ok()) << read.message;
    EXPECT_EQ(packed.format, reproject::ColorFormat::rgba16f);
    EXPECT_EQ(packed.channels, channels);
    ASSERT_EQ(packed.bytes.size(), 5u * 4u * 8u);
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 5; ++x) {
        std::uint16_t h[4];
        std::memcpy(h, packed.bytes.data() + (y * 5 + x) * 8, sizeof h);
        const bool grey = channels <= 2;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(h[c], half(at(image, grey ? 0 : c, x, y)).bits()) << x << "," << y;
        const float alpha = channels == 2 ? at(image, 1, x, y) : channels == 4 ? at(image, 3, x, y) : 1.0f;
        EXPECT_EQ(h[3], half(alpha).bits());
      }
    }
    TempFile out("out.exr");
    ASSERT_TRUE(io::write_exr_packed(out.path, packed.view(), channels).ok());
    io::LoadedImage back;
    ASSERT_TRUE(io::read_image(out.path, &back).ok());
    EXPECT_EQ(back.bit_depth, 16);
    ASSERT_EQ(back.image.channels(), channels);
    for (int c = 0; c < channels; ++c) {
      for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 5; ++x) EXPECT_EQ(at(back.image, c, x, y), static_cast<float>(half(at(image, c, x, y))));
      }
    }
  }
}

// ------------------------------------------------------------------------------------------------
// Raw buffers

TEST(Raw, RowsPackedLittleEndianAndSizeChecked) {
  // Two rows of three 16-bit words, from a buffer with a padded stride.
  const std::uint16_t words[2][4] = {{0x0102, 0x0304, 0x0506, 0xFFFF}, {0x0708, 0x090A, 0x0B0C, 0xFFFF}};
  TempFile file("d.raw");
  ASSERT_TRUE(io::write_raw(file.path, reinterpret_cast<const std::uint8_t*>(words), 6, 2, 8, 2).ok());
  const std::vector<unsigned char> bytes = file_bytes(file.path);
  EXPECT_EQ(bytes, (std::vector<unsigned char>{2, 1, 4, 3, 6, 5, 8, 7, 10, 9, 12, 11}));
  std::vector<std::uint8_t> back;
  ASSERT_TRUE(io::read_raw(file.path, 12, 2, "a 3x2 unorm16 buffer", &back).ok());
  std::uint16_t first = 0;
  std::memcpy(&first, back.data(), 2);
  EXPECT_EQ(first, 0x0102);
  EXPECT_TRUE(io::check_raw_size(file.path, 12, "x").ok());

  const io::IoStatus wrong = io::read_raw(file.path, 16, 2, "a 4x2 unorm16 buffer", &back);
  EXPECT_EQ(wrong.error, io::IoError::size_mismatch);
  EXPECT_TRUE(back.empty());
  EXPECT_TRUE(contains(wrong.message, "holds 12 bytes, but a 4x2 unorm16 buffer is 16 bytes")) << wrong.message;
  EXPECT_EQ(io::check_raw_size(file.path, 11, "x").error, io::IoError::size_mismatch);
  EXPECT_EQ(io::check_raw_size(file.path + ".missing", 12, "x").error, io::IoError::open_failed);
  EXPECT_EQ(io::check_raw_size(::testing::TempDir(), 12, "x").error, io::IoError::read_failed);
}

// ------------------------------------------------------------------------------------------------
// Exr

Image depth_ramp(int width, int height) {
  return make_image(width, height, 1, [](int, int x, int y) { return 0.5f + 1.75f * static_cast<float>(x) + 100.0f * static_cast<float>(y); });
}

TEST(Exr, RoundTripFloatRgbaAndZ) {
  const Image color = make_image(11, 6, 4, float_value);
  const Image depth = depth_ramp(11, 6);
  TempFile file("float.exr");
  const FloatPlane depth_plane = depth.plane(0);
  const io::IoStatus written = io::write_exr(file.path, color.color(), &depth_plane);
  ASSERT_TRUE(written.ok()) << written.message;
  EXPECT_EQ(rptest::leftovers(file.path), 0);

  io::LoadedImage loaded;
  const io::IoStatus read = io::read_exr(file.path, &loaded);
  ASSERT_TRUE(read.ok()) << read.message;
  EXPECT_EQ(loaded.format, io::FileFormat::exr);
  EXPECT_EQ(loaded.bit_depth, 32);
  EXPECT_EQ(loaded.color_layer, "");
  EXPECT_EQ(loaded.depth_channel, "Z");
  expect_same_bits(color, loaded.image);
  expect_same_bits(depth, loaded.depth);

  // The depth alone, through the front end.
  io::LoadedImage only_depth;
  ASSERT_TRUE(io::read_depth(file.path, &only_depth).ok());
  expect_same_bits(depth, only_depth.image);
  EXPECT_TRUE(only_depth.depth.empty());

  // The same colour from an interleaved RGBA buffer (float slices read it in place, strided).
  Image interleaved(11, 6, 4, ColorLayout::interleaved_rgba);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 11; ++x) {
      for (int c = 0; c < 4; ++c) interleaved.mutable_plane(0).row(y)[4 * x + c] = at(color, c, x, y);
    }
  }
  TempFile rgba("interleaved.exr");
  ASSERT_TRUE(io::write_exr(rgba.path, interleaved.color(), &depth_plane).ok());
  ASSERT_TRUE(io::read_exr(rgba.path, &loaded).ok());
  expect_same_bits(color, loaded.image);
  expect_same_bits(depth, loaded.depth);
}

TEST(Exr, RoundTripHalfRgbaAndZWithinHalfPrecision) {
  // In half range; values that are not halves round to the nearest one.
  const Image color = make_image(8, 3, 4, [](int c, int x, int y) {
    return (static_cast<float>(x) - 3.3f) * 0.37f + static_cast<float>(y) * 900.1f - static_cast<float>(c) * 0.01f;
  });
  const Image depth = depth_ramp(8, 3);
  // Interleaved input, to cover that path too.
  Image interleaved(8, 3, 4, ColorLayout::interleaved_rgba);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 8; ++x) {
      for (int c = 0; c < 4; ++c) interleaved.mutable_plane(0).row(y)[4 * x + c] = at(color, c, x, y);
    }
  }
  io::ExrWriteOptions options;
  options.color_type = io::ExrPixelType::half;
  options.depth_type = io::ExrPixelType::half;
  TempFile file("half.exr");
  const FloatPlane depth_plane = depth.plane(0);
  ASSERT_TRUE(io::write_exr(file.path, interleaved.color(), &depth_plane, options).ok());

  io::LoadedImage loaded;
  const io::IoStatus read = io::read_exr(file.path, &loaded);
  ASSERT_TRUE(read.ok()) << read.message;
  EXPECT_EQ(loaded.bit_depth, 16);
  ASSERT_EQ(loaded.image.channels(), 4);
  ASSERT_FALSE(loaded.depth.empty());
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 8; ++x) {
      for (int c = 0; c < 4; ++c) {
        const float value = at(color, c, x, y);
        const float got = at(loaded.image, c, x, y);
        EXPECT_EQ(got, static_cast<float>(half(value))) << "c " << c << " x " << x << " y " << y;
        // Half keeps 11 significant bits: relative error at most 2^-11 in the normal range.
        EXPECT_LE(std::fabs(got - value), std::ldexp(std::fabs(value), -11) + 1e-7f);
      }
      EXPECT_EQ(at(loaded.depth, 0, x, y), static_cast<float>(half(at(depth, 0, x, y))));
    }
  }
}

TEST(Exr, RoundTripGreyAndDepthOnly) {
  const Image grey = make_image(5, 4, 1, float_value);
  TempFile file("grey.exr");
  ASSERT_TRUE(io::write_image(file.path, grey.color()).ok());
  io::LoadedImage loaded;
  ASSERT_TRUE(io::read_image(file.path, &loaded).ok());
  expect_same_bits(grey, loaded.image);
  EXPECT_TRUE(loaded.depth.empty());
  // A single "Y" channel is also accepted as a depth image.
  ASSERT_TRUE(io::read_depth(file.path, &loaded).ok());
  EXPECT_EQ(loaded.depth_channel, "Y");
  expect_same_bits(grey, loaded.image);

  // Grey + alpha: Y and A.
  const Image grey_alpha = make_image(5, 4, 2, float_value);
  TempFile ya("ya.exr");
  ASSERT_TRUE(io::write_image(ya.path, grey_alpha.color()).ok());
  ASSERT_TRUE(io::read_image(ya.path, &loaded).ok());
  expect_same_bits(grey_alpha, loaded.image);

  const Image depth = depth_ramp(5, 4);
  TempFile only("depth.exr");
  ASSERT_TRUE(io::write_depth(only.path, depth.plane(0)).ok());
  ASSERT_TRUE(io::read_depth(only.path, &loaded).ok());
  EXPECT_EQ(loaded.depth_channel, "Z");
  expect_same_bits(depth, loaded.image);
  // read_exr accepts a depth-only file; read_image wants colour.
  ASSERT_TRUE(io::read_exr(only.path, &loaded).ok());
  EXPECT_TRUE(loaded.image.empty());
  expect_same_bits(depth, loaded.depth);
  const io::IoStatus no_color = io::read_image(only.path, &loaded);
  EXPECT_EQ(no_color.error, io::IoError::unsupported) << no_color.message;
  EXPECT_TRUE(contains(no_color.message, "no colour channels")) << no_color.message;
}

// Writes an EXR with the given channels (name -> type) over the data window `window`; channel k
// holds 10 * k + x + 0.5 y at pixel (x, y) in data-window coordinates. Returns the expected
// plane of channel k.
struct RawChannel {
  std::string name;
  Imf::PixelType type;
};

float raw_value(int k, int x, int y) { return 10.0f * static_cast<float>(k) + static_cast<float>(x) + 0.5f * static_cast<float>(y); }

void write_raw_exr(const std::string& path, const std::vector<RawChannel>& channels,
                   const Imath::Box2i& window = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(3, 2))) {
  const int width = window.max.x - window.min.x + 1;
  const int height = window.max.y - window.min.y + 1;
  Imf::Header header(Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(window.max.x, window.max.y)), window);
  std::vector<std::vector<float>> floats;
  std::vector<std::vector<half>> halves;
  floats.reserve(channels.size());
  halves.reserve(channels.size());
  Imf::FrameBuffer frame;
  for (std::size_t k = 0; k < channels.size(); ++k) {
    header.channels().insert(channels[k].name, Imf::Channel(channels[k].type));
    std::vector<float> values(static_cast<std::size_t>(width * height));
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) values[static_cast<std::size_t>(y * width + x)] = raw_value(static_cast<int>(k), x, y);
    }
    if (channels[k].type == Imf::HALF) {
      halves.emplace_back(values.begin(), values.end());
      frame.insert(channels[k].name, Imf::Slice::Make(Imf::HALF, halves.back().data(), window));
    } else {
      floats.push_back(values);
      frame.insert(channels[k].name, Imf::Slice::Make(Imf::FLOAT, floats.back().data(), window));
    }
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(height);
}

// Plane `plane` of `image` holds raw channel k.
void expect_raw_channel(const Image& image, int plane, int k) {
  ASSERT_GT(image.channels(), plane);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      ASSERT_EQ(image.plane(plane).row(y)[x], raw_value(k, x, y)) << "plane " << plane << " x " << x << " y " << y;
    }
  }
}

TEST(Exr, BlenderMultilayerNames) {
  // As Blender writes a multilayer EXR: the beauty pass, the depth, and other passes whose
  // channels look like depth (the Mist pass's Z, the Normal pass's X/Y/Z) but are not.
  TempFile file("blender.exr");
  const std::vector<RawChannel> channels = {
      {"ViewLayer.Combined.A", Imf::HALF}, {"ViewLayer.Combined.B", Imf::HALF},  // k = 0, 1
      {"ViewLayer.Combined.G", Imf::HALF}, {"ViewLayer.Combined.R", Imf::HALF},  // k = 2, 3
      {"ViewLayer.Depth.Z", Imf::FLOAT},   {"ViewLayer.Mist.Z", Imf::FLOAT},     // k = 4, 5
      {"ViewLayer.Normal.X", Imf::HALF},   {"ViewLayer.Normal.Y", Imf::HALF},    // k = 6, 7
      {"ViewLayer.Normal.Z", Imf::HALF},                                         // k = 8
  };
  write_raw_exr(file.path, channels);
  io::LoadedImage loaded;
  const io::IoStatus status = io::read_image(file.path, &loaded);
  ASSERT_TRUE(status.ok()) << status.message;
  EXPECT_EQ(loaded.color_layer, "ViewLayer.Combined");
  EXPECT_EQ(loaded.depth_channel, "ViewLayer.Depth.Z");
  EXPECT_EQ(loaded.bit_depth, 32);  // the depth is float
  ASSERT_EQ(loaded.image.channels(), 4);
  expect_raw_channel(loaded.image, 0, 3);  // R
  expect_raw_channel(loaded.image, 1, 2);  // G
  expect_raw_channel(loaded.image, 2, 1);  // B
  expect_raw_channel(loaded.image, 3, 0);  // A
  expect_raw_channel(loaded.depth, 0, 4);

  // Without the Depth pass, neither the Mist Z nor the Normal Z is taken as depth.
  TempFile no_depth("blender-no-depth.exr");
  std::vector<RawChannel> rest = channels;
  rest.erase(rest.begin() + 4);
  write_raw_exr(no_depth.path, rest);
  ASSERT_TRUE(io::read_image(no_depth.path, &loaded).ok());
  EXPECT_TRUE(loaded.depth.empty());
  EXPECT_EQ(loaded.depth_channel, "");
  const io::IoStatus refused = io::read_depth(no_depth.path, &loaded);
  EXPECT_EQ(refused.error, io::IoError::unsupported) << refused.message;
  EXPECT_TRUE(contains(refused.message, "no depth channel")) << refused.message;
  EXPECT_TRUE(contains(refused.message, "'ViewLayer.Mist.Z'")) << refused.message;  // the channels are listed

  // A single-layer file with a lower-case "depth" beside R, G, B, and any other *.Z.
  TempFile lower("lower.exr");
  write_raw_exr(lower.path, {{"B", Imf::FLOAT}, {"G", Imf::FLOAT}, {"R", Imf::FLOAT}, {"depth", Imf::HALF}});
  ASSERT_TRUE(io::read_image(lower.path, &loaded).ok());
  EXPECT_EQ(loaded.depth_channel, "depth");
  expect_raw_channel(loaded.depth, 0, 3);
  TempFile other("other.exr");
  write_raw_exr(other.path, {{"render.B", Imf::FLOAT}, {"render.G", Imf::FLOAT}, {"render.R", Imf::FLOAT},
                             {"render.Z", Imf::FLOAT}});
  ASSERT_TRUE(io::read_image(other.path, &loaded).ok());
  EXPECT_EQ(loaded.color_layer, "render");
  EXPECT_EQ(loaded.depth_channel, "render.Z");
}

TEST(Exr, AmbiguousLayersAreErrorsUnlessNamed) {
  TempFile file("two-layers.exr");
  write_raw_exr(file.path, {{"left.B", Imf::FLOAT}, {"left.Depth.Z", Imf::FLOAT}, {"left.G", Imf::FLOAT},
                            {"left.R", Imf::FLOAT}, {"right.B", Imf::FLOAT}, {"right.Depth.Z", Imf::FLOAT},
                            {"right.G", Imf::FLOAT}, {"right.R", Imf::FLOAT}});
  io::LoadedImage loaded;
  io::IoStatus status = io::read_exr(file.path, &loaded);
  EXPECT_EQ(status.error, io::IoError::unsupported) << status.message;
  EXPECT_TRUE(contains(status.message, "several colour layers ('left', 'right')")) << status.message;

  io::ExrReadOptions options;
  options.color_layer = "right";
  status = io::read_exr(file.path, &loaded, options);
  EXPECT_EQ(status.error, io::IoError::unsupported) << status.message;
  EXPECT_TRUE(contains(status.message, "several depth channels")) << status.message;

  options.depth_channel = "right.Depth.Z";
  status = io::read_exr(file.path, &loaded, options);
  ASSERT_TRUE(status.ok()) << status.message;
  expect_raw_channel(loaded.image, 0, 7);
  expect_raw_channel(loaded.depth, 0, 5);

  options.depth_channel = "";  // no depth
  ASSERT_TRUE(io::read_exr(file.path, &loaded, options).ok());
  EXPECT_TRUE(loaded.depth.empty());

  options.depth_channel = "nope.Z";
  status = io::read_exr(file.path, &loaded, options);
  EXPECT_EQ(status.error, io::IoError::unsupported) << status.message;
  EXPECT_TRUE(contains(status.message, "no channel 'nope.Z'")) << status.message;
}

TEST(Exr, WritesLayerNamesItReadsBack) {
  const Image color = make_image(4, 3, 4, float_value);
  const Image depth = depth_ramp(4, 3);
  io::ExrWriteOptions options;
  options.color_layer = "ViewLayer.Combined";
  options.depth_channel = "ViewLayer.Depth.Z";
  TempFile file("layered.exr");
  const FloatPlane depth_plane = depth.plane(0);
  ASSERT_TRUE(io::write_exr(file.path, color.color(), &depth_plane, options).ok());
  io::LoadedImage loaded;
  ASSERT_TRUE(io::read_exr(file.path, &loaded).ok());
  EXPECT_EQ(loaded.color_layer, "ViewLayer.Combined");
  EXPECT_EQ(loaded.depth_channel, "ViewLayer.Depth.Z");
  expect_same_bits(color, loaded.image);
  expect_same_bits(depth, loaded.depth);
}

TEST(Exr, DataWindowAwayFromTheOrigin) {
  TempFile file("window.exr");
  write_raw_exr(file.path, {{"B", Imf::FLOAT}, {"G", Imf::FLOAT}, {"R", Imf::HALF}, {"Z", Imf::FLOAT}},
                Imath::Box2i(Imath::V2i(10, 20), Imath::V2i(14, 22)));
  io::LoadedImage loaded;
  ASSERT_TRUE(io::read_exr(file.path, &loaded).ok());
  EXPECT_EQ(loaded.image.width(), 5);
  EXPECT_EQ(loaded.image.height(), 3);
  expect_raw_channel(loaded.image, 0, 2);
  expect_raw_channel(loaded.image, 2, 0);
  expect_raw_channel(loaded.depth, 0, 3);
}

TEST(Exr, TiledFilesAreRead) {
  // 5x3 in 2x2 tiles: partial tiles on the right and at the bottom.
  const int width = 5;
  const int height = 3;
  Imf::Header header(width, height);
  header.setTileDescription(Imf::TileDescription(2, 2, Imf::ONE_LEVEL));
  const char* const names[] = {"B", "G", "R", "Z"};
  std::vector<std::vector<float>> planes(4, std::vector<float>(width * height));
  Imf::FrameBuffer frame;
  for (int k = 0; k < 4; ++k) {
    header.channels().insert(names[k], Imf::Channel(Imf::FLOAT));
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) planes[k][static_cast<std::size_t>(y * width + x)] = raw_value(k, x, y);
    }
    frame.insert(names[k], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[k].data()), sizeof(float),
                                      sizeof(float) * width));
  }
  TempFile file("tiled.exr");
  {
    Imf::TiledOutputFile out(file.path.c_str(), header);
    out.setFrameBuffer(frame);
    out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
  }
  io::LoadedImage loaded;
  const io::IoStatus status = io::read_exr(file.path, &loaded);
  ASSERT_TRUE(status.ok()) << status.message;
  ASSERT_EQ(loaded.image.width(), width);
  expect_raw_channel(loaded.image, 0, 2);
  expect_raw_channel(loaded.image, 1, 1);
  expect_raw_channel(loaded.image, 2, 0);
  expect_raw_channel(loaded.depth, 0, 3);
}

TEST(Exr, BadFilesAreErrorsWithClearMessages) {
  io::LoadedImage loaded;
  const io::IoStatus missing = io::read_exr(temp_path("missing.exr"), &loaded);
  EXPECT_EQ(missing.error, io::IoError::open_failed) << missing.message;
  EXPECT_TRUE(contains(missing.message, "missing.exr")) << missing.message;

  // A PNG under an .exr name: the extension picks the reader, the reader checks the magic.
  TempFile png("png.exr");
  const Image small(2, 2, 3);
  ASSERT_TRUE(io::write_png(png.path, small.color()).ok());
  io::IoStatus status = io::read_image(png.path, &loaded);
  EXPECT_EQ(status.error, io::IoError::not_this_format) << status.message;
  EXPECT_TRUE(contains(status.message, "not an OpenEXR file")) << status.message;

  // Truncated: inside the magic, inside the header, inside the pixels.
  const Image color = make_image(64, 32, 4, float_value);
  TempFile whole("whole.exr");
  ASSERT_TRUE(io::write_exr(whole.path, color.color()).ok());
  const std::vector<unsigned char> bytes = file_bytes(whole.path);
  ASSERT_GT(bytes.size(), 2000u);
  TempFile cut("cut.exr");
  for (std::size_t size : {std::size_t{2}, std::size_t{40}, bytes.size() / 2, bytes.size() - 1}) {
    write_bytes(cut.path, std::vector<unsigned char>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(size)));
    status = io::read_exr(cut.path, &loaded);
    EXPECT_EQ(status.error, io::IoError::truncated) << size << " bytes: " << status.message;
    EXPECT_TRUE(contains(status.message, "truncated")) << status.message;
    EXPECT_TRUE(loaded.image.empty());
  }

  // The right magic and garbage after it.
  std::vector<unsigned char> garbage(bytes.begin(), bytes.begin() + 4);
  garbage.resize(300, 0xA5);
  write_bytes(cut.path, garbage);
  status = io::read_exr(cut.path, &loaded);
  EXPECT_TRUE(status.error == io::IoError::corrupt || status.error == io::IoError::truncated) << status.message;
  EXPECT_TRUE(loaded.image.empty());
}

TEST(Exr, WriteErrors) {
  const Image color(4, 3, 3);
  const Image depth(5, 3, 1);
  const FloatPlane depth_plane = depth.plane(0);
  TempFile file("bad.exr");
  io::IoStatus status = io::write_exr(file.path, color.color(), &depth_plane);
  EXPECT_EQ(status.error, io::IoError::size_mismatch) << status.message;
  EXPECT_TRUE(contains(status.message, "size mismatch: depth is 5x3, colour is 4x3")) << status.message;

  status = io::write_exr(file.path, ColorView{}, nullptr);
  EXPECT_EQ(status.error, io::IoError::invalid_argument) << status.message;

  io::ExrWriteOptions clash;
  clash.depth_channel = "G";
  const Image depth_ok(4, 3, 1);
  const FloatPlane depth_ok_plane = depth_ok.plane(0);
  status = io::write_exr(file.path, color.color(), &depth_ok_plane, clash);
  EXPECT_EQ(status.error, io::IoError::invalid_argument) << status.message;
  EXPECT_FALSE(std::filesystem::exists(file.path));
  EXPECT_EQ(rptest::leftovers(file.path), 0);

  // Into a directory that does not exist: nothing is left anywhere.
  status = io::write_exr(temp_path("missing-dir") + "/out.exr", color.color());
  EXPECT_EQ(status.error, io::IoError::write_failed) << status.message;
}

// ------------------------------------------------------------------------------------------------
// TemporaryFiles

// A writer's temporary file is known to the signal clean-up for as long as it exists: a child
// process writes the same small file over and over (create, write, rename), and is killed at
// random moments; its handler removes what is tracked, as the tool's does. CI once found a
// temporary left behind by a signal that came between the file's creation and its tracking.
#if defined(_WIN32)
// Windows: the writer is this program again, started with REPROJECT_TEST_WRITE_LOOP naming the
// file, in a console of its own; the test sends it Ctrl-C, which Windows handles on a thread of
// the writer's own while its writes go on, and the handler removes what is tracked and exits, as
// the tool's does when a command does not stop in time (tools/cli/files.cpp). From the clean-up on,
// creating a temporary fails ("the program is being interrupted"), so a write under way may fail
// before the handler ends the process: the writer then waits to be ended (exit 0) instead of
// exiting with its own failure code first.
std::atomic<bool> g_interrupted{false};

BOOL WINAPI remove_temporaries_and_exit(DWORD) {
  g_interrupted.store(true);
  io::remove_temporary_files();
  ExitProcess(0);
}

const bool g_writer_child = [] {
  const char* output = std::getenv("REPROJECT_TEST_WRITE_LOOP");
  if (output == nullptr) return false;
  SetConsoleCtrlHandler(remove_temporaries_and_exit, TRUE);
  Image plane(8, 4, 1);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 8; ++x) plane.plane_data()[y * plane.stride() + x] = static_cast<float>(x + 8 * y);
  }
  std::ofstream(std::getenv("REPROJECT_TEST_WRITE_READY")) << "ready";
  for (;;) {
    if (io::write_depth(output, plane.plane(0)).ok()) continue;
    if (g_interrupted.load()) Sleep(INFINITE);  // the handler is ending the process
    ExitProcess(3);
  }
}();
#else
extern "C" void remove_temporaries_and_exit(int) {
  io::remove_temporary_files();
  _exit(0);
}

#endif

TEST(TemporaryFiles, SignalAtAnyMomentOfAWriteLeavesNone) {
  const std::filesystem::path dir = temp_path("signals");
  std::filesystem::create_directories(dir);
  const std::string output = (dir / "out.pfm").string();
  const Image plane = make_image(8, 4, 1, [](int, int x, int y) { return static_cast<float>(x + 8 * y); });
  // Signals land anywhere within a few writes: as long as one write takes here (an emulator, a
  // loaded machine, a sanitizer build can be 30 times slower than a native release build).
  const auto started = std::chrono::steady_clock::now();
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(io::write_depth(output, plane.plane(0)).ok());
  const long write_us = static_cast<long>(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - started).count() / 4);
  const long spread_us = std::max(3000L, 4 * write_us);
  std::filesystem::remove(output);
  std::mt19937 random(20261124u);
  int leftovers = 0, writes_done = 0;
#if defined(_WIN32)
  (void)spread_us;
  const std::filesystem::path ready = temp_path("writer-ready");
  wchar_t self[MAX_PATH];
  ASSERT_GT(GetModuleFileNameW(nullptr, self, MAX_PATH), 0u);
  SetEnvironmentVariableW(L"REPROJECT_TEST_WRITE_LOOP", rptest::wide(output).c_str());
  SetEnvironmentVariableW(L"REPROJECT_TEST_WRITE_READY", ready.wstring().c_str());
  // Each round starts a process under Wine (a few hundred ms): fewer rounds than on POSIX, each
  // interrupting at a random moment of up to 50 ms of writes.
  for (int round = 0; round < 40 && leftovers == 0; ++round) {
    std::filesystem::remove(ready);
    PROCESS_INFORMATION child = {};
    ASSERT_TRUE(rptest::start_process(rptest::quote_argument(self), L"", nullptr, nullptr, true, &child));
    for (int waited = 0; waited < 20000 && !std::filesystem::exists(ready); waited += 5) Sleep(5);
    ASSERT_TRUE(std::filesystem::exists(ready)) << "the writer did not start";
    std::this_thread::sleep_for(std::chrono::microseconds(200 + static_cast<long>(random() % 50000)));
    ASSERT_TRUE(rptest::send_ctrl_c(child.dwProcessId)) << GetLastError();
    ASSERT_EQ(WaitForSingleObject(child.hProcess, 20000), WAIT_OBJECT_0) << "the writer did not stop";
    DWORD code = 1;
    GetExitCodeProcess(child.hProcess, &code);
    CloseHandle(child.hThread);
    CloseHandle(child.hProcess);
    ASSERT_EQ(code, 0u) << "the writer failed or died";
#else
  for (int round = 0; round < 150 && leftovers == 0; ++round) {
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      struct sigaction action = {};
      action.sa_handler = remove_temporaries_and_exit;
      sigemptyset(&action.sa_mask);
      sigaction(SIGTERM, &action, nullptr);
      (void)!::write(ready[1], "r", 1);
      for (;;) {
        if (!io::write_depth(output, plane.plane(0)).ok()) _exit(3);
      }
    }
    ::close(ready[1]);
    char byte = 0;
    ASSERT_EQ(::read(ready[0], &byte, 1), 1);
    ::close(ready[0]);
    std::this_thread::sleep_for(std::chrono::microseconds(200 + static_cast<long>(random() % spread_us)));
    ::kill(child, SIGTERM);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the writer failed or died: " << status;
#endif
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name == "out.pfm") {
        ++writes_done;
        continue;
      }
      ++leftovers;
      ADD_FAILURE() << name << " left after the signal of round " << round;
    }
  }
#if defined(_WIN32)
  SetEnvironmentVariableW(L"REPROJECT_TEST_WRITE_LOOP", nullptr);
  SetEnvironmentVariableW(L"REPROJECT_TEST_WRITE_READY", nullptr);
#endif
  EXPECT_GT(writes_done, 0) << "no write finished before its signal";
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
}

// ------------------------------------------------------------------------------------------------
// LargeFiles

// Files of 2 GB and more, sparse (only their headers are written): sizes and offsets are 64-bit on
// every system (Windows' `long` and its default `struct stat` size are 32-bit).
TEST(LargeFiles, SizesAndOffsetsPastTwoGigabytes) {
  TempFile pfm("large.pfm");
  const std::string header = "PF\n16384 16384\n-1.0\n";  // RGB floats: 3 GiB of pixels
  const std::uint64_t whole = header.size() + 3ULL * 4 * 16384 * 16384;
  write_text(pfm.path, header);
  std::filesystem::resize_file(io::os::to_path(pfm.path), whole);
  io::ImageInfo info;
  io::IoStatus status = io::read_image_info(pfm.path, &info);
  ASSERT_TRUE(status.ok()) << status.message;
  EXPECT_EQ(info.width, 16384);
  EXPECT_EQ(info.channels, 3);
  EXPECT_TRUE(io::check_raw_size(pfm.path, whole, "the buffer").ok());
  status = io::check_raw_size(pfm.path, whole - (1ULL << 32), "the buffer");
  EXPECT_EQ(status.error, io::IoError::size_mismatch);
  EXPECT_TRUE(contains(status.message, "holds " + std::to_string(whole) + " bytes")) << status.message;

  std::FILE* file = io::os::open_file(pfm.path, "rb");
  ASSERT_NE(file, nullptr);
  const std::uint64_t far = (5ULL << 30) / 2 + 7;  // 2.5 GiB and a few bytes
  EXPECT_TRUE(io::os::seek(file, far));
  EXPECT_EQ(io::os::tell(file), static_cast<std::int64_t>(far));
  EXPECT_EQ(std::fgetc(file), 0);  // a hole reads as zeros
  EXPECT_EQ(io::os::tell(file), static_cast<std::int64_t>(far + 1));
  io::os::FileStatus file_status;
  ASSERT_TRUE(io::os::file_status(file, &file_status));
  EXPECT_TRUE(file_status.regular);
  EXPECT_EQ(file_status.size, static_cast<std::int64_t>(whole));
  std::fclose(file);

  // One byte short of its pixels: truncated, counted in 64 bits.
  std::filesystem::resize_file(io::os::to_path(pfm.path), whole - 1);
  status = io::read_image_info(pfm.path, &info);
  EXPECT_EQ(status.error, io::IoError::truncated) << status.message;
}

// ------------------------------------------------------------------------------------------------
// Formats

TEST(Formats, DetectsTheFormatByExtension) {
  EXPECT_EQ(io::format_from_path("a.png"), io::FileFormat::png);
  EXPECT_EQ(io::format_from_path("dir/B.PNG"), io::FileFormat::png);
  EXPECT_EQ(io::format_from_path("x.y.Pfm"), io::FileFormat::pfm);
  EXPECT_EQ(io::format_from_path("/tmp/render.exr"), io::FileFormat::exr);
  EXPECT_EQ(io::format_from_path("render.exr.bak"), io::FileFormat::unknown);
  EXPECT_EQ(io::format_from_path("dir.exr/file"), io::FileFormat::unknown);
  EXPECT_EQ(io::format_from_path("noextension"), io::FileFormat::unknown);
  EXPECT_EQ(io::format_from_path("photo.jpg"), io::FileFormat::unknown);
  EXPECT_EQ(io::format_from_path(".png"), io::FileFormat::png);
  EXPECT_STREQ(io::to_string(io::FileFormat::exr), "exr");
  EXPECT_STREQ(io::to_string(io::IoError::size_mismatch), "size_mismatch");
}

TEST(Formats, GenericRoundTripOfEveryFormat) {
  const Image rgb = make_image(6, 4, 3, [](int c, int x, int y) { return static_cast<float>((x * 40 + y * 9 + c * 70) % 256); });
  const Image depth = make_image(6, 4, 1, [](int, int x, int y) { return static_cast<float>(x * 1000 + y * 7); });
  const std::map<std::string, io::FileFormat> extensions = {
      {"png", io::FileFormat::png}, {"PFM", io::FileFormat::pfm}, {"exr", io::FileFormat::exr}};
  for (const auto& [extension, format] : extensions) {
    TempFile file("colour." + extension);
    ASSERT_TRUE(io::write_image(file.path, rgb.color()).ok()) << extension;
    io::LoadedImage loaded;
    const io::IoStatus status = io::read_image(file.path, &loaded);
    ASSERT_TRUE(status.ok()) << extension << ": " << status.message;
    EXPECT_EQ(loaded.format, format);
    expect_same_bits(rgb, loaded.image);

    TempFile depth_file("depth." + extension);
    ASSERT_TRUE(io::write_depth(depth_file.path, depth.plane(0)).ok()) << extension;
    ASSERT_TRUE(io::read_depth(depth_file.path, &loaded).ok()) << extension;
    EXPECT_EQ(loaded.format, format);
    expect_same_bits(depth, loaded.image);
  }
}

TEST(Formats, UnknownExtensionIsAnError) {
  const Image rgb(2, 2, 3);
  TempFile file("image.jpg");
  io::IoStatus status = io::write_image(file.path, rgb.color());
  EXPECT_EQ(status.error, io::IoError::not_this_format) << status.message;
  EXPECT_TRUE(contains(status.message, "unknown image file extension")) << status.message;
  EXPECT_FALSE(std::filesystem::exists(file.path));
  EXPECT_EQ(io::write_depth(file.path, rgb.plane(0)).error, io::IoError::not_this_format);

  write_text(file.path, "not really a jpeg");
  io::LoadedImage loaded;
  status = io::read_image(file.path, &loaded);
  EXPECT_EQ(status.error, io::IoError::not_this_format) << status.message;
  EXPECT_TRUE(contains(status.message, "unknown image file extension")) << status.message;
  EXPECT_EQ(io::read_depth(file.path, &loaded).error, io::IoError::not_this_format);
  EXPECT_EQ(io::read_image(file.path, nullptr).error, io::IoError::invalid_argument);
}

TEST(Formats, TheExtensionNotTheContentPicksTheReader) {
  const Image rgb(3, 2, 3);
  TempFile png("real.png");
  ASSERT_TRUE(io::write_image(png.path, rgb.color()).ok());
  TempFile pfm("fake.pfm");
  write_bytes(pfm.path, file_bytes(png.path));
  io::LoadedImage loaded;
  const io::IoStatus status = io::read_image(pfm.path, &loaded);
  EXPECT_EQ(status.error, io::IoError::not_this_format) << status.message;
  EXPECT_TRUE(contains(status.message, "not a PFM file")) << status.message;

  TempFile fake_png("fake.png");
  ASSERT_TRUE(io::write_pfm(fake_png.path, rgb.color()).ok());
  EXPECT_EQ(io::read_image(fake_png.path, &loaded).error, io::IoError::not_this_format);
}

TEST(Formats, PlanesOfDifferentSizesAreRefusedByEveryWriter) {
  const Image big(4, 3, 1);
  const Image small(4, 2, 1);
  const ColorView mixed = ColorView::planar({big.plane(0), small.plane(0), big.plane(0)});
  for (const char* extension : {"png", "pfm", "exr"}) {
    TempFile file(std::string("mixed.") + extension);
    const io::IoStatus status = io::write_image(file.path, mixed);
    EXPECT_EQ(status.error, io::IoError::size_mismatch) << extension << ": " << status.message;
    EXPECT_TRUE(contains(status.message, "size mismatch: plane 1 is 4x2, plane 0 is 4x3")) << status.message;
    EXPECT_FALSE(std::filesystem::exists(file.path));
    EXPECT_EQ(rptest::leftovers(file.path), 0);
  }
}

TEST(Formats, DepthFromARgbPfmIsAnUnsupportedLayout) {
  const Image rgb(3, 2, 3);
  TempFile file("rgb.pfm");
  ASSERT_TRUE(io::write_image(file.path, rgb.color()).ok());
  io::LoadedImage loaded;
  const io::IoStatus status = io::read_depth(file.path, &loaded);
  EXPECT_EQ(status.error, io::IoError::unsupported) << status.message;
  EXPECT_TRUE(contains(status.message, "unsupported channel layout")) << status.message;
}

// ------------------------------------------------------------------------------------------------
// StereoViews

// Left pixels are 100 + 10 x + y + 1000 c; right pixels 500 + 10 x + y + 1000 c.
Image eye(int width, int height, int channels, float base) {
  return make_image(width, height, channels, [&](int c, int x, int y) {
    return base + 10.0f * static_cast<float>(x) + static_cast<float>(y) + 1000.0f * static_cast<float>(c);
  });
}

TEST(StereoViews, SideBySideFullPlacesLeftThenRight) {
  const Image left = eye(3, 2, 3, 100.0f);
  const Image right = eye(3, 2, 3, 500.0f);
  Image out;
  ASSERT_TRUE(io::side_by_side(left.color(), right.color(), &out).ok());
  ASSERT_EQ(out.width(), 6);
  ASSERT_EQ(out.height(), 2);
  ASSERT_EQ(out.channels(), 3);
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) {
        EXPECT_EQ(at(out, c, x, y), at(left, c, x, y));
        EXPECT_EQ(at(out, c, x + 3, y), at(right, c, x, y));
      }
    }
  }
}

TEST(StereoViews, SideBySideHalfAveragesPairs) {
  const Image left = eye(5, 2, 1, 100.0f);  // odd width: each eye becomes 3 columns
  const Image right = eye(5, 2, 1, 500.0f);
  Image out;
  ASSERT_TRUE(io::side_by_side(left.color(), right.color(), &out, io::StereoPacking::half).ok());
  ASSERT_EQ(out.width(), 6);
  ASSERT_EQ(out.height(), 2);
  // Row 1 of the left eye is 101, 111, 121, 131, 141: pairs (101, 111), (121, 131), (141).
  const float expected[] = {106.0f, 126.0f, 141.0f, 506.0f, 526.0f, 541.0f};
  for (int x = 0; x < 6; ++x) EXPECT_EQ(at(out, 0, x, 1), expected[x]) << "x " << x;
}

TEST(StereoViews, TopBottomFullAndHalf) {
  const Image left = eye(2, 3, 3, 100.0f);
  const Image right = eye(2, 3, 3, 500.0f);
  Image out;
  ASSERT_TRUE(io::top_bottom(left.color(), right.color(), &out).ok());
  ASSERT_EQ(out.width(), 2);
  ASSERT_EQ(out.height(), 6);
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < 3; ++y) {
      for (int x = 0; x < 2; ++x) {
        EXPECT_EQ(at(out, c, x, y), at(left, c, x, y));
        EXPECT_EQ(at(out, c, x, y + 3), at(right, c, x, y));
      }
    }
  }
  ASSERT_TRUE(io::top_bottom(left.color(), right.color(), &out, io::StereoPacking::half).ok());
  ASSERT_EQ(out.height(), 4);  // 3 rows -> 2 per eye
  // Column 1, channel 2 of the left eye: 2110, 2111, 2112 -> 2110.5, 2112.
  EXPECT_EQ(at(out, 2, 1, 0), 2110.5f);
  EXPECT_EQ(at(out, 2, 1, 1), 2112.0f);
  EXPECT_EQ(at(out, 2, 1, 2), 2510.5f);
  EXPECT_EQ(at(out, 2, 1, 3), 2512.0f);
}

TEST(StereoViews, AnaglyphPlainTakesRedFromLeftAndGreenBlueFromRight) {
  const Image left = eye(4, 2, 3, 1.0f);
  // The right eye as interleaved RGBA, to read both layouts.
  const Image right_planes = eye(4, 2, 4, 3.0f);
  Image right(4, 2, 4, ColorLayout::interleaved_rgba);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) {
      for (int c = 0; c < 4; ++c) right.mutable_plane(0).row(y)[4 * x + c] = at(right_planes, c, x, y);
    }
  }
  Image out;
  ASSERT_TRUE(io::anaglyph(left.color(), right.color(), &out, io::AnaglyphMethod::plain).ok());
  ASSERT_EQ(out.channels(), 3);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) {
      EXPECT_EQ(at(out, 0, x, y), at(left, 0, x, y));
      EXPECT_EQ(at(out, 1, x, y), at(right_planes, 1, x, y));
      EXPECT_EQ(at(out, 2, x, y), at(right_planes, 2, x, y));
    }
  }
}

TEST(StereoViews, AnaglyphDuboisMatchesAHandComputedPixel) {
  Image left(2, 1, 3);
  Image right(2, 1, 3);
  // Pixel 0: left (200, 100, 50), right (30, 150, 220). Pixel 1: white in both eyes.
  const float l[3] = {200, 100, 50};
  const float r[3] = {30, 150, 220};
  for (int c = 0; c < 3; ++c) {
    at(left, c, 0, 0) = l[c];
    at(right, c, 0, 0) = r[c];
    at(left, c, 1, 0) = 255.0f;
    at(right, c, 1, 0) = 255.0f;
  }
  Image out;
  ASSERT_TRUE(io::anaglyph(left.color(), right.color(), &out).ok());  // Dubois by default
  // By hand from the published matrices, e.g. R = 0.4561*200 + 0.500484*100 + 0.176381*50
  //   - 0.0434706*30 - 0.0879388*150 - 0.00155529*220 = 135.2503482.
  EXPECT_NEAR(at(out, 0, 0, 0), 135.2503482f, 1e-3f);
  EXPECT_NEAR(at(out, 1, 0, 0), 104.754369f, 1e-3f);
  EXPECT_NEAR(at(out, 2, 0, 0), 245.322911f, 1e-3f);
  // Each output row of [left | right] sums to 1: white stays white (after clamping).
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(at(out, c, 1, 0), 255.0f, 2e-3f) << c;

  // Out-of-range results are clamped: pure red left and black right gives negative G and B.
  at(left, 0, 0, 0) = 255.0f;
  at(left, 1, 0, 0) = 0.0f;
  at(left, 2, 0, 0) = 0.0f;
  for (int c = 0; c < 3; ++c) at(right, c, 0, 0) = 0.0f;
  ASSERT_TRUE(io::anaglyph(left.color(), right.color(), &out).ok());
  EXPECT_NEAR(at(out, 0, 0, 0), 0.4561f * 255.0f, 1e-3f);
  EXPECT_EQ(at(out, 1, 0, 0), 0.0f);
  EXPECT_EQ(at(out, 2, 0, 0), 0.0f);
}

TEST(StereoViews, StatusImageColors) {
  const std::uint8_t statuses[] = {0, 1, 2, 3, 7};
  std::uint8_t data[5];
  std::memcpy(data, statuses, sizeof data);
  const reproject::BytePlane plane{data, 5, 1, 5};
  Image out;
  ASSERT_TRUE(io::status_image(plane, &out).ok());
  const float expected[5][3] = {{0, 0, 0}, {255, 0, 0}, {0, 128, 255}, {255, 255, 0}, {255, 0, 255}};
  for (int x = 0; x < 5; ++x) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(at(out, c, x, 0), expected[x][c]) << "status " << int(statuses[x]);
  }
  // Every status value has its own colour.
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 5; ++b) {
      EXPECT_NE(io::status_color(statuses[a]), io::status_color(statuses[b]));
    }
  }
  EXPECT_EQ(io::status_image(reproject::BytePlane{}, &out).error, io::IoError::invalid_argument);
}

TEST(StereoViews, HeatMapIsMonotonic) {
  std::array<float, 3> previous = io::heat_color(0.0f);
  EXPECT_EQ(previous, (std::array<float, 3>{0, 0, 0}));
  for (int i = 1; i <= 300; ++i) {
    const std::array<float, 3> color = io::heat_color(static_cast<float>(i) / 300.0f);
    for (int c = 0; c < 3; ++c) EXPECT_GE(color[c], previous[c]) << "t " << i << "/300";
    EXPECT_GT(color[0] + color[1] + color[2], previous[0] + previous[1] + previous[2]) << "t " << i << "/300";
    previous = color;
  }
  EXPECT_EQ(previous, (std::array<float, 3>{255, 255, 255}));
  EXPECT_EQ(io::heat_color(2.0f), previous);  // clamped
  EXPECT_EQ(io::heat_color(-1.0f), (std::array<float, 3>{0, 0, 0}));

  // Errors 0, 1, 2, 4 (and a NaN) with a fixed maximum of 3 and with the image's own maximum.
  Image a(5, 1, 1);
  Image b(5, 1, 1);
  const float errors[] = {0.0f, 1.0f, 2.0f, 4.0f};
  for (int x = 0; x < 4; ++x) {
    at(a, 0, x, 0) = 10.0f;
    at(b, 0, x, 0) = 10.0f - errors[x];
  }
  at(a, 0, 4, 0) = std::numeric_limits<float>::quiet_NaN();
  Image out;
  ASSERT_TRUE(io::error_heat_map(a.color(), b.color(), &out, 3.0f).ok());
  const float fixed[4][3] = {{0, 0, 0}, {255, 0, 0}, {255, 255, 0}, {255, 255, 255}};
  for (int x = 0; x < 4; ++x) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(at(out, c, x, 0), fixed[x][c], 1e-3f) << "x " << x << " c " << c;
  }
  EXPECT_EQ(at(out, 0, 4, 0), 255.0f);  // NaN: magenta
  EXPECT_EQ(at(out, 1, 4, 0), 0.0f);
  EXPECT_EQ(at(out, 2, 4, 0), 255.0f);

  ASSERT_TRUE(io::error_heat_map(a.color(), b.color(), &out).ok());  // max = 4, the largest finite
  for (int c = 0; c < 3; ++c) EXPECT_EQ(at(out, c, 3, 0), 255.0f);
  EXPECT_NEAR(at(out, 0, 2, 0), 255.0f, 1e-3f);  // t = 0.5: R full, G half
  EXPECT_NEAR(at(out, 1, 2, 0), 127.5f, 1e-3f);

  // Several channels: the largest difference counts.
  Image a3(1, 1, 3);
  Image b3(1, 1, 3);
  at(a3, 1, 0, 0) = 1.0f;
  at(b3, 2, 0, 0) = 3.0f;
  ASSERT_TRUE(io::error_heat_map(a3.color(), b3.color(), &out, 3.0f).ok());
  for (int c = 0; c < 3; ++c) EXPECT_EQ(at(out, c, 0, 0), 255.0f);

  EXPECT_EQ(io::error_heat_map(a.color(), b.color(), &out, -1.0f).error, io::IoError::invalid_argument);
  EXPECT_EQ(io::error_heat_map(a.color(), b.color(), &out, std::numeric_limits<float>::infinity()).error,
            io::IoError::invalid_argument);
  EXPECT_TRUE(out.empty());
}

TEST(StereoViews, MismatchedOrBadInputsAreErrors) {
  const Image left = eye(4, 3, 3, 0.0f);
  const Image narrow = eye(3, 3, 3, 0.0f);
  const Image grey = eye(4, 3, 1, 0.0f);
  Image out;
  io::IoStatus status = io::side_by_side(left.color(), narrow.color(), &out);
  EXPECT_EQ(status.error, io::IoError::size_mismatch) << status.message;
  EXPECT_TRUE(contains(status.message, "size mismatch: left image is 4x3, right image is 3x3")) << status.message;
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(io::top_bottom(left.color(), narrow.color(), &out).error, io::IoError::size_mismatch);
  EXPECT_EQ(io::anaglyph(left.color(), narrow.color(), &out).error, io::IoError::size_mismatch);
  EXPECT_EQ(io::error_heat_map(left.color(), narrow.color(), &out).error, io::IoError::size_mismatch);

  status = io::side_by_side(left.color(), grey.color(), &out);
  EXPECT_EQ(status.error, io::IoError::invalid_argument) << status.message;
  EXPECT_TRUE(contains(status.message, "channel count mismatch")) << status.message;
  // The anaglyph takes a grey eye as R = G = B.
  ASSERT_TRUE(io::anaglyph(left.color(), grey.color(), &out, io::AnaglyphMethod::plain).ok());
  EXPECT_EQ(at(out, 1, 2, 1), at(grey, 0, 2, 1));

  EXPECT_EQ(io::side_by_side(ColorView{}, left.color(), &out).error, io::IoError::invalid_argument);
  EXPECT_EQ(io::side_by_side(left.color(), left.color(), nullptr).error, io::IoError::invalid_argument);
}

}  // namespace
