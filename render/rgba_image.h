// An 8-bit RGBA image in memory and its PNG file (libpng): what the density rasterizer
// hands to gnuplot, and what a caller who wants only the picture keeps.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace chatterlab::render {

struct RgbaImage {
  int width = 0;
  int height = 0;
  // width * height pixels of R, G, B, A (straight, not premultiplied, alpha), row 0 at the
  // top, as in image files.
  std::vector<std::uint8_t> rgba;

  // The 4 bytes of pixel (column, row); no bounds check beyond the vector's.
  const std::uint8_t* at(int column, int row) const {
    return rgba.data() + 4 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                              static_cast<std::size_t>(column));
  }
};

// Writes an RGBA PNG (8 bits per channel). zlib level 3: a mostly transparent density image of
// 1000 x 600 pixels encodes in ~10 ms to ~0.1-1 MB; level 9 saves ~10 % at ~5x the time.
// Throws RenderError naming the file when it cannot be written or the image is malformed.
void write_png(const RgbaImage& image, const std::filesystem::path& path, int zlib_level = 3);

// Reads any PNG (palette, grey, 16-bit: converted) as 8-bit RGBA. Throws RenderError naming
// the file and libpng's message.
RgbaImage read_png(const std::filesystem::path& path);

}  // namespace chatterlab::render
