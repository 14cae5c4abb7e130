// Picture helpers on top of imageio/stereo_views: scaling to its 0..255 convention, marking the
// pixels a comparison did not measure, and cropping, tiling and labelling for the comparison
// mosaic (the README's picture).
#include <algorithm>
#include <cctype>
#include <cstring>

#include "cli.hpp"

namespace reproject::cli {

Image to_picture_scale(const ColorView& color) {
  Image out(color.width(), color.height(), color.channels);
  if (out.empty()) fail(kExitRuntime, "out of memory for a picture");
  for (int c = 0; c < color.channels; ++c) {
    for (int y = 0; y < color.height(); ++y) {
      const float* src = color.plane[c].row(y);
      float* dst = out.plane_data(c) + y * out.stride();
      for (int x = 0; x < color.width(); ++x) dst[x] = src[x] * 255.0f;
    }
  }
  return out;
}

void check_picture(const io::IoStatus& status, const char* what) {
  if (!status) fail(kExitRuntime, std::string("cannot make the ") + what + ": " + status.message);
}

void mark_unmeasured(Image* picture, const std::uint8_t* mask) {
  const float dim[3] = {20.0f, 30.0f, 70.0f};
  for (int y = 0; y < picture->height(); ++y) {
    for (int x = 0; x < picture->width(); ++x) {
      if (mask[static_cast<std::size_t>(y) * picture->width() + x]) continue;
      for (int c = 0; c < std::min(3, picture->channels()); ++c) picture->plane_data(c)[y * picture->stride() + x] = dim[c];
    }
  }
}

namespace {

float at(const Image& image, int c, int x, int y) {
  const int plane = std::min(c, image.channels() - 1);  // grey: repeat
  return image.plane_data(plane)[y * image.stride() + x];
}

}  // namespace

Image crop(const Image& image, int x0, int y0, int w, int h) {
  x0 = std::max(0, std::min(x0, image.width() - 1));
  y0 = std::max(0, std::min(y0, image.height() - 1));
  w = std::max(1, std::min(w, image.width() - x0));
  h = std::max(1, std::min(h, image.height() - y0));
  Image out(w, h, 3);
  if (out.empty()) fail(kExitRuntime, "out of memory for a picture");
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) out.plane_data(c)[y * out.stride() + x] = at(image, c, x0 + x, y0 + y);
    }
  }
  return out;
}

Image downscale(const Image& image, int factor) {
  factor = std::max(1, factor);
  const int w = std::max(1, image.width() / factor), h = std::max(1, image.height() / factor);
  Image out(w, h, 3);
  if (out.empty()) fail(kExitRuntime, "out of memory for a picture");
  const float inv = 1.0f / static_cast<float>(factor * factor);
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        float sum = 0.0f;
        for (int dy = 0; dy < factor; ++dy) {
          for (int dx = 0; dx < factor; ++dx) {
            sum += at(image, c, std::min(x * factor + dx, image.width() - 1), std::min(y * factor + dy, image.height() - 1));
          }
        }
        out.plane_data(c)[y * out.stride() + x] = sum * inv;
      }
    }
  }
  return out;
}

Image mosaic(const std::vector<const Image*>& tiles, int columns, int gap) {
  int cell_w = 1, cell_h = 1;
  for (const Image* t : tiles) {
    cell_w = std::max(cell_w, t->width());
    cell_h = std::max(cell_h, t->height());
  }
  columns = std::max(1, columns);
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  const int w = columns * cell_w + (columns + 1) * gap, h = rows * cell_h + (rows + 1) * gap;
  Image out(w, h, 3);
  if (out.empty()) fail(kExitRuntime, "out of memory for a picture");
  for (int c = 0; c < 3; ++c) {
    for (int y = 0; y < h; ++y) std::fill_n(out.plane_data(c) + y * out.stride(), w, 24.0f);
  }
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const Image& t = *tiles[i];
    const int ox = gap + static_cast<int>(i % columns) * (cell_w + gap);
    const int oy = gap + static_cast<int>(i / columns) * (cell_h + gap);
    for (int c = 0; c < 3; ++c) {
      for (int y = 0; y < t.height(); ++y) {
        for (int x = 0; x < t.width(); ++x) out.plane_data(c)[(oy + y) * out.stride() + ox + x] = at(t, c, x, y);
      }
    }
  }
  return out;
}

namespace {

// A 5x7 pixel font: seven rows of five columns each, '#' set. Letters are capitals (labels
// are lower-case text; both map here).
struct Glyph {
  char ch;
  const char* rows[7];
};
const Glyph kFont[] = {
    {'a', {" ### ", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
    {'b', {"#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### "}},
    {'c', {" ### ", "#   #", "#    ", "#    ", "#    ", "#   #", " ### "}},
    {'d', {"#### ", "#   #", "#   #", "#   #", "#   #", "#   #", "#### "}},
    {'e', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####"}},
    {'f', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#    "}},
    {'g', {" ### ", "#   #", "#    ", "# ###", "#   #", "#   #", " ####"}},
    {'h', {"#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
    {'i', {" ### ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
    {'j', {"  ###", "   # ", "   # ", "   # ", "   # ", "#  # ", " ##  "}},
    {'k', {"#   #", "#  # ", "# #  ", "##   ", "# #  ", "#  # ", "#   #"}},
    {'l', {"#    ", "#    ", "#    ", "#    ", "#    ", "#    ", "#####"}},
    {'m', {"#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #"}},
    {'n', {"#   #", "#   #", "##  #", "# # #", "#  ##", "#   #", "#   #"}},
    {'o', {" ### ", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
    {'p', {"#### ", "#   #", "#   #", "#### ", "#    ", "#    ", "#    "}},
    {'q', {" ### ", "#   #", "#   #", "#   #", "# # #", "#  # ", " ## #"}},
    {'r', {"#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #"}},
    {'s', {" ####", "#    ", "#    ", " ### ", "    #", "    #", "#### "}},
    {'t', {"#####", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {'u', {"#   #", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
    {'v', {"#   #", "#   #", "#   #", "#   #", "#   #", " # # ", "  #  "}},
    {'w', {"#   #", "#   #", "#   #", "# # #", "# # #", "# # #", " # # "}},
    {'x', {"#   #", "#   #", " # # ", "  #  ", " # # ", "#   #", "#   #"}},
    {'y', {"#   #", "#   #", " # # ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {'z', {"#####", "    #", "   # ", "  #  ", " #   ", "#    ", "#####"}},
    {'0', {" ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### "}},
    {'1', {"  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
    {'2', {" ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####"}},
    {'3', {"#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### "}},
    {'4', {"   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # "}},
    {'5', {"#####", "#    ", "#### ", "    #", "    #", "#   #", " ### "}},
    {'6', {"  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### "}},
    {'7', {"#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   "}},
    {'8', {" ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### "}},
    {'9', {" ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  "}},
    {'.', {"     ", "     ", "     ", "     ", "     ", " ##  ", " ##  "}},
    {',', {"     ", "     ", "     ", "     ", " ##  ", "  #  ", " #   "}},
    {':', {"     ", " ##  ", " ##  ", "     ", " ##  ", " ##  ", "     "}},
    {'%', {"##   ", "##  #", "   # ", "  #  ", " #   ", "#  ##", "   ##"}},
    {'/', {"     ", "    #", "   # ", "  #  ", " #   ", "#    ", "     "}},
    {'-', {"     ", "     ", "     ", "#####", "     ", "     ", "     "}},
    {'+', {"     ", "  #  ", "  #  ", "#####", "  #  ", "  #  ", "     "}},
    {'=', {"     ", "     ", "#####", "     ", "#####", "     ", "     "}},
    {'(', {"   # ", "  #  ", " #   ", " #   ", " #   ", "  #  ", "   # "}},
    {')', {" #   ", "  #  ", "   # ", "   # ", "   # ", "  #  ", " #   "}},
    {'~', {"     ", "     ", " #   ", "# # #", "   # ", "     ", "     "}},
    {'|', {"  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {' ', {"     ", "     ", "     ", "     ", "     ", "     ", "     "}},
};

const Glyph* glyph(char ch) {
  const char lower = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  for (const Glyph& g : kFont) {
    if (g.ch == lower) return &g;
  }
  return nullptr;
}

}  // namespace

void label(Image* image, int x, int y, const std::string& text, int scale) {
  const int advance = 6 * scale, pad = 2 * scale;
  const int box_w = static_cast<int>(text.size()) * advance - scale + 2 * pad, box_h = 7 * scale + 2 * pad;
  auto put = [&](int px, int py, float v) {
    if (px < 0 || py < 0 || px >= image->width() || py >= image->height()) return;
    for (int c = 0; c < std::min(3, image->channels()); ++c) image->plane_data(c)[py * image->stride() + px] = v;
  };
  for (int py = 0; py < box_h; ++py) {
    for (int px = 0; px < box_w; ++px) put(x + px, y + py, 16.0f);
  }
  for (std::size_t i = 0; i < text.size(); ++i) {
    const Glyph* g = glyph(text[i]);
    if (g == nullptr) continue;
    for (int r = 0; r < 7; ++r) {
      for (int col = 0; col < 5; ++col) {
        if (g->rows[r][col] != '#') continue;
        for (int sy = 0; sy < scale; ++sy) {
          for (int sx = 0; sx < scale; ++sx) {
            put(x + pad + static_cast<int>(i) * advance + col * scale + sx, y + pad + r * scale + sy, 255.0f);
          }
        }
      }
    }
  }
}

}  // namespace reproject::cli
