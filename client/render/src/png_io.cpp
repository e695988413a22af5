#include "vscan/render/png_io.h"

#include <atomic>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <vector>

#include <png.h>
#include <unistd.h>

namespace vscan::render {
namespace {

// libpng reports errors through a callback; the message is kept and control returns to setjmp.
struct PngErrors {
  char message[256] = "unknown libpng error";
};

[[noreturn]] void OnPngError(png_structp png, png_const_charp message) {
  auto* errors = static_cast<PngErrors*>(png_get_error_ptr(png));
  std::snprintf(errors->message, sizeof(errors->message), "%s", message);
  png_longjmp(png, 1);
}

void OnPngWarning(png_structp, png_const_charp) {}

// The setjmp frames below hold only trivially destructible locals; what they fill lives in the
// caller, so a longjmp skips no destructor.
bool WriteBody(png_structp png, png_infop info, std::FILE* file, const Image& image,
               const std::vector<png_bytep>& rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, file);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  return true;
}

bool ReadBody(png_structp png, png_infop info, std::FILE* file, Image& image, std::vector<png_bytep>& rows,
              PngErrors& errors) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, file);
  png_read_info(png, info);
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_strip_alpha(png);
  png_set_gray_to_rgb(png);
  png_read_update_info(png, info);
  const uint32_t width = png_get_image_width(png, info);
  const uint32_t height = png_get_image_height(png, info);
  if (png_get_rowbytes(png, info) != size_t{width} * 3) {
    std::snprintf(errors.message, sizeof(errors.message), "unexpected row size after conversion to RGB");
    return false;
  }
  image = Image(width, height);
  rows.resize(height);
  for (uint32_t y = 0; y < height; ++y) rows[y] = image.rgb.data() + size_t{y} * width * 3;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  return true;
}

}  // namespace

Status WritePng(const Image& image, const std::string& path) {
  if (image.width == 0 || image.height == 0 || image.rgb.size() != size_t{image.width} * image.height * 3) {
    return InvalidArgument(path + ": image has no pixels or the wrong number of bytes");
  }
  static std::atomic<unsigned> counter{0};
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (file == nullptr) {
    const int err = errno;
    const std::string msg = path + ": cannot create: " + std::strerror(err);
    return err == ENOENT ? NotFound(msg) : FailedPrecondition(msg);
  }
  std::vector<png_bytep> rows(image.height);
  for (uint32_t y = 0; y < image.height; ++y) {
    rows[y] = const_cast<png_bytep>(image.rgb.data() + size_t{y} * image.width * 3);
  }
  PngErrors errors;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, OnPngError, OnPngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  const bool written = info != nullptr && WriteBody(png, info, file, image, rows);
  png_destroy_write_struct(&png, &info);
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    std::remove(tmp.c_str());
    return DataLoss(path + ": " + (written ? std::string("close: ") + std::strerror(errno) : errors.message));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string msg = path + ": rename: " + std::strerror(errno);
    std::remove(tmp.c_str());
    return DataLoss(msg);
  }
  return Status::Ok();
}

StatusOr<Image> ReadPng(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return NotFound(path + ": cannot open: " + std::strerror(errno));
  png_byte signature[8] = {};
  if (std::fread(signature, 1, sizeof(signature), file) != sizeof(signature) ||
      png_sig_cmp(signature, 0, sizeof(signature)) != 0) {
    std::fclose(file);
    return InvalidArgument(path + ": not a PNG file");
  }
  PngErrors errors;
  Image image;
  std::vector<png_bytep> rows;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors, OnPngError, OnPngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info != nullptr) png_set_sig_bytes(png, sizeof(signature));
  const bool read = info != nullptr && ReadBody(png, info, file, image, rows, errors);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(file);
  if (!read) return DataLoss(path + ": " + errors.message);
  return image;
}

}  // namespace vscan::render
