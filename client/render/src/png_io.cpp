#include "vscan/render/png_io.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <span>

#include <unistd.h>

#include "vscan/common/png_codec.h"

namespace vscan::render {

Status WritePng(const Image& image, const std::string& path) {
  if (image.width == 0 || image.height == 0 || image.rgb.size() != size_t{image.width} * image.height * 3) {
    return InvalidArgument(path + ": image has no pixels or the wrong number of bytes");
  }
  const StatusOr<std::string> bytes = EncodePng(image.width, image.height, std::span<const uint8_t>(image.rgb));
  if (!bytes.ok()) return DataLoss(path + ": " + bytes.status().message());
  static std::atomic<unsigned> counter{0};
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (file == nullptr) {
    const int err = errno;
    const std::string msg = path + ": cannot create: " + std::strerror(err);
    return err == ENOENT ? NotFound(msg) : FailedPrecondition(msg);
  }
  const bool written = std::fwrite(bytes->data(), 1, bytes->size(), file) == bytes->size();
  const int write_err = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    const int err = written ? errno : write_err;
    const std::string msg = path + ": " + (written ? "close: " : "write: ") + std::strerror(err);
    std::remove(tmp.c_str());
    return DataLoss(msg);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string msg = path + ": rename: " + std::strerror(errno);
    std::remove(tmp.c_str());
    return DataLoss(msg);
  }
  return Status::Ok();
}

StatusOr<Image> ReadPng(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return NotFound(path + ": cannot open: " + std::strerror(errno));
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) return DataLoss(path + ": read failed");
  if (!HasPngSignature(bytes)) return InvalidArgument(path + ": not a PNG file");
  StatusOr<RgbPixels> pixels = DecodePng(bytes);
  if (!pixels.ok()) return DataLoss(path + ": " + pixels.status().message());
  Image image;
  image.width = pixels->width;
  image.height = pixels->height;
  image.rgb = std::move(pixels->rgb);
  return image;
}

}  // namespace vscan::render
