#include "robot_registry/bundle_codec.h"

#include "store/byte_codec.h"

namespace vscan::robot_registry {
namespace {

constexpr std::string_view kMagic = "VSRB";
constexpr uint32_t kVersion = 1;

}  // namespace

std::string EncodeBundle(const robot::BundleFiles& files) {
  store::ByteWriter out;
  out.Raw(kMagic);
  out.U32(kVersion);
  out.U32(static_cast<uint32_t>(files.size()));
  for (const auto& [path, bytes] : files) {
    out.Bytes(path);
    out.Bytes(bytes);
  }
  return out.Take();
}

StatusOr<std::vector<robot::BundleFile>> DecodeBundle(std::string_view blob) {
  store::ByteReader in(blob, "robot bundle");
  ASSIGN_OR_RETURN(std::string_view magic, in.Raw(kMagic.size()));
  if (magic != kMagic) return DataLoss("robot bundle: not a vscan robot bundle");
  ASSIGN_OR_RETURN(uint32_t version, in.U32());
  if (version != kVersion) return DataLoss("robot bundle: unknown format version " + std::to_string(version));
  ASSIGN_OR_RETURN(uint32_t count, in.U32());
  // Each file takes at least 16 bytes, so a corrupt count cannot make us allocate much.
  if (count > in.remaining() / 16) return in.Short();
  std::vector<robot::BundleFile> files(count);
  for (robot::BundleFile& file : files) {
    ASSIGN_OR_RETURN(std::string_view path, in.Bytes());
    ASSIGN_OR_RETURN(std::string_view bytes, in.Bytes());
    file.path = path;
    file.bytes = bytes;
  }
  if (!in.done()) return in.Short();
  return files;
}

}  // namespace vscan::robot_registry
