#include "render/rgba_image.h"

#include <png.h>

#include <array>
#include <csetjmp>
#include <cstdio>
#include <memory>
#include <string>

#include "render/render_error.h"

namespace chatterlab::render {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// libpng reports errors by longjmp to png_jmpbuf; the message is kept for the RenderError.
struct PngErrorText {
  std::array<char, 200> text{};
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* error = static_cast<PngErrorText*>(png_get_error_ptr(png));
  std::snprintf(error->text.data(), error->text.size(), "%s", message ? message : "libpng error");
  png_longjmp(png, 1);
}
void on_png_warning(png_structp, png_const_charp) {}

// The libpng calls between setjmp and any longjmp: no C++ object with a destructor lives
// in this frame, so the jump skips nothing.
bool write_png_rows(png_structp png, png_infop info, std::FILE* file, const RgbaImage& image,
                    int zlib_level) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, file);
  png_set_compression_level(png, zlib_level);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
               static_cast<png_uint_32>(image.height), 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int row = 0; row < image.height; ++row) png_write_row(png, image.at(0, row));
  png_write_end(png, nullptr);
  return true;
}

}  // namespace

void write_png(const RgbaImage& image, const std::filesystem::path& path, int zlib_level) {
  const std::size_t expected =
      4 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() != expected) {
    throw RenderError("cannot write " + path.string() + ": image of " +
                      std::to_string(image.width) + " x " + std::to_string(image.height) +
                      " pixels holds " + std::to_string(image.rgba.size()) + " bytes, not " +
                      std::to_string(expected));
  }
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw RenderError("cannot write " + path.string());
  PngErrorText error;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, on_png_error, on_png_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw RenderError("cannot write " + path.string() + ": out of memory in libpng");
  }
  const bool ok = write_png_rows(png, info, file.get(), image, zlib_level);
  png_destroy_write_struct(&png, &info);
  if (!ok) throw RenderError("cannot write " + path.string() + ": " + error.text.data());
  if (std::fflush(file.get()) != 0 || std::ferror(file.get())) {
    throw RenderError("cannot write " + path.string());
  }
}

RgbaImage read_png(const std::filesystem::path& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    throw RenderError("cannot read PNG " + path.string() + ": " + png.message);
  }
  png.format = PNG_FORMAT_RGBA;
  RgbaImage image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.rgba.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw RenderError("cannot read PNG " + path.string() + ": " + message);
  }
  return image;
}

}  // namespace chatterlab::render
