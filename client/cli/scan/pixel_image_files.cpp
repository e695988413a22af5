#include "scan/pixel_image_files.h"

#include <filesystem>
#include <fstream>

#include "vscan/common/png_codec.h"

namespace vscan::cli {
namespace {

Status WriteBytes(const std::string& bytes, const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) return Internal(path.string() + ": cannot write");
  return Status::Ok();
}

}  // namespace

int PrepareImagesDir(Context& ctx, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec)) {
    return ctx.LocalError(NotFound("--images: cannot make directory " + dir));
  }
  return kExitOk;
}

int WritePixelImages(Context& ctx, const client::PixelImages& images, const std::string& dir) {
  const std::filesystem::path root(dir);
  StatusOr<std::string> reasons = EncodeGray8Png(images.width, images.height, images.reasons);
  if (!reasons.ok()) return ctx.LocalError(reasons.status());
  StatusOr<std::string> gray = EncodeGray16Png(images.width, images.height, images.gray);
  if (!gray.ok()) return ctx.LocalError(gray.status());
  for (const auto& [bytes, name] : {std::pair{&*reasons, "reasons.png"}, std::pair{&*gray, "gray.png"}}) {
    const Status written = WriteBytes(*bytes, root / name);
    if (!written.ok()) return ctx.LocalError(written);
  }
  ctx.Say("wrote " + (root / "reasons.png").string() + " and " + (root / "gray.png").string());
  return kExitOk;
}

}  // namespace vscan::cli
