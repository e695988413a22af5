#include "vscan/common/png_codec.h"

#include <bit>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <new>

#include <png.h>
#include <zlib.h>

namespace vscan {
namespace {

constexpr size_t kSignatureBytes = 8;
// Larger images are refused before their rows are allocated.
constexpr uint32_t kMaxDecodedSide = 1u << 15;

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

void AppendBytes(png_structp png, png_bytep data, size_t size) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  bool appended = true;
  try {
    out->append(reinterpret_cast<const char*>(data), size);
  } catch (const std::bad_alloc&) {
    appended = false;
  }
  if (!appended) png_error(png, "out of memory");
}

void FlushNothing(png_structp) {}

struct ByteSource {
  std::string_view bytes;
  size_t at = 0;
};

void ReadBytes(png_structp png, png_bytep data, size_t size) {
  auto* source = static_cast<ByteSource*>(png_get_io_ptr(png));
  if (size > source->bytes.size() - source->at) png_error(png, "the PNG data ends early");
  std::memcpy(data, source->bytes.data() + source->at, size);
  source->at += size;
}

// How one image is laid out in rows for libpng.
struct PngLayout {
  uint32_t width = 0;
  uint32_t height = 0;
  int bit_depth = 8;
  int color_type = PNG_COLOR_TYPE_RGB;
  size_t bytes_per_pixel = 3;
  // Row filters and deflate strategy: libpng's adaptive choice tries all five filters on every
  // row, which costs 2-8x the time of one fixed filter on the images vscan writes by the hundred.
  int filters = PNG_ALL_FILTERS;
  int strategy = -1;  // zlib's default
};

// The setjmp frames below hold only trivially destructible locals; what they fill lives in the
// caller, so a longjmp skips no destructor.

bool EncodeBody(png_structp png, png_infop info, const PngLayout& layout, std::string& out,
                const std::vector<png_bytep>& rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, &out, AppendBytes, FlushNothing);
  png_set_IHDR(png, info, layout.width, layout.height, layout.bit_depth, layout.color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, layout.filters);
  if (layout.strategy >= 0) png_set_compression_strategy(png, layout.strategy);
  png_write_info(png, info);
  if (layout.bit_depth == 16 && std::endian::native == std::endian::little) png_set_swap(png);
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  return true;
}

StatusOr<std::string> EncodeRows(const PngLayout& layout, const uint8_t* pixels) {
  std::vector<png_bytep> rows(layout.height);
  const size_t row_bytes = size_t{layout.width} * layout.bytes_per_pixel;
  for (uint32_t y = 0; y < layout.height; ++y) rows[y] = const_cast<png_bytep>(pixels + size_t{y} * row_bytes);
  PngErrors errors;
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, OnPngError, OnPngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  const bool encoded = info != nullptr && EncodeBody(png, info, layout, out, rows);
  png_destroy_write_struct(&png, &info);
  if (!encoded) return DataLoss(std::string("PNG: ") + errors.message);
  return out;
}

bool DecodeBody(png_structp png, png_infop info, ByteSource& source, RgbPixels& image, std::vector<png_bytep>& rows,
                PngErrors& errors) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_read_fn(png, &source, ReadBytes);
  png_set_user_limits(png, kMaxDecodedSide, kMaxDecodedSide);
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
  image.width = width;
  image.height = height;
  image.rgb.assign(size_t{width} * height * 3, 0);
  rows.resize(height);
  for (uint32_t y = 0; y < height; ++y) rows[y] = image.rgb.data() + size_t{y} * width * 3;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  return true;
}

// Reads the stored values into bytes (host order) and the size into image; wrong_kind is set (and
// false returned) for a PNG that is not 8-bit or 16-bit greyscale.
bool DecodeGrayBody(png_structp png, png_infop info, ByteSource& source, GrayPixels& image, std::vector<uint8_t>& bytes,
                    std::vector<png_bytep>& rows, bool& wrong_kind) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_read_fn(png, &source, ReadBytes);
  png_set_user_limits(png, kMaxDecodedSide, kMaxDecodedSide);
  png_read_info(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  if (png_get_color_type(png, info) != PNG_COLOR_TYPE_GRAY || (bit_depth != 8 && bit_depth != 16)) {
    wrong_kind = true;
    return false;
  }
  if (bit_depth == 16 && std::endian::native == std::endian::little) png_set_swap(png);
  png_read_update_info(png, info);
  image.width = png_get_image_width(png, info);
  image.height = png_get_image_height(png, info);
  image.bit_depth = bit_depth;
  const size_t row_bytes = size_t{image.width} * (bit_depth / 8);
  bytes.assign(row_bytes * image.height, 0);
  rows.resize(image.height);
  for (uint32_t y = 0; y < image.height; ++y) rows[y] = bytes.data() + size_t{y} * row_bytes;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  return true;
}

}  // namespace

bool HasPngSignature(std::string_view bytes) {
  return bytes.size() >= kSignatureBytes &&
         png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, kSignatureBytes) == 0;
}

StatusOr<std::string> EncodePng(uint32_t width, uint32_t height, std::span<const uint8_t> rgb) {
  if (width == 0 || height == 0 || rgb.size() != size_t{width} * height * 3) {
    return InvalidArgument("PNG: the image has no pixels or the wrong number of bytes");
  }
  return EncodeRows({width, height, 8, PNG_COLOR_TYPE_RGB, 3}, rgb.data());
}

StatusOr<std::string> EncodeGray8Png(uint32_t width, uint32_t height, std::span<const uint8_t> values) {
  if (width == 0 || height == 0 || values.size() != size_t{width} * height) {
    return InvalidArgument("PNG: the image has no pixels or the wrong number of values");
  }
  // Masks: long runs of one value, which run-length deflate packs as small as the default, 7x faster.
  return EncodeRows({width, height, 8, PNG_COLOR_TYPE_GRAY, 1, PNG_FILTER_NONE, Z_RLE}, values.data());
}

StatusOr<std::string> EncodeGray16Png(uint32_t width, uint32_t height, std::span<const uint16_t> values) {
  if (width == 0 || height == 0 || values.size() != size_t{width} * height) {
    return InvalidArgument("PNG: the image has no pixels or the wrong number of values");
  }
  // Depth and instance images: smooth down the columns, so the Up filter alone packs them as well.
  return EncodeRows({width, height, 16, PNG_COLOR_TYPE_GRAY, 2, PNG_FILTER_UP, -1},
                    reinterpret_cast<const uint8_t*>(values.data()));
}

StatusOr<RgbPixels> DecodePng(std::string_view bytes) {
  if (!HasPngSignature(bytes)) return InvalidArgument("PNG: not a PNG stream");
  PngErrors errors;
  ByteSource source{bytes, kSignatureBytes};
  RgbPixels image;
  std::vector<png_bytep> rows;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors, OnPngError, OnPngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info != nullptr) png_set_sig_bytes(png, kSignatureBytes);
  const bool decoded = info != nullptr && DecodeBody(png, info, source, image, rows, errors);
  png_destroy_read_struct(&png, &info, nullptr);
  if (!decoded) return DataLoss(std::string("PNG: ") + errors.message);
  return image;
}

StatusOr<GrayPixels> DecodeGrayPng(std::string_view bytes) {
  if (!HasPngSignature(bytes)) return InvalidArgument("PNG: not a PNG stream");
  PngErrors errors;
  ByteSource source{bytes, kSignatureBytes};
  GrayPixels image;
  std::vector<uint8_t> stored;
  std::vector<png_bytep> rows;
  bool wrong_kind = false;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors, OnPngError, OnPngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info != nullptr) png_set_sig_bytes(png, kSignatureBytes);
  const bool decoded = info != nullptr && DecodeGrayBody(png, info, source, image, stored, rows, wrong_kind);
  png_destroy_read_struct(&png, &info, nullptr);
  if (wrong_kind) return InvalidArgument("PNG: not an 8-bit or 16-bit greyscale image");
  if (!decoded) return DataLoss(std::string("PNG: ") + errors.message);
  image.values.resize(size_t{image.width} * image.height);
  if (image.bit_depth == 16) {
    std::memcpy(image.values.data(), stored.data(), stored.size());
  } else {
    for (size_t i = 0; i < stored.size(); ++i) image.values[i] = stored[i];
  }
  return image;
}

}  // namespace vscan
