#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

#include "vscan/client/types.h"

namespace vscan::client {
namespace {

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

v1::MeshFormat MeshFormatFromPath(const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext == ".ply") return v1::MESH_FORMAT_PLY;
  if (ext == ".obj") return v1::MESH_FORMAT_OBJ;
  if (ext == ".stl") return v1::MESH_FORMAT_STL;
  return v1::MESH_FORMAT_UNSPECIFIED;
}

v1::CloudFormat CloudFormatFromPath(const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext == ".ply") return v1::CLOUD_FORMAT_PLY;
  if (ext == ".pcd") return v1::CLOUD_FORMAT_PCD;
  return v1::CLOUD_FORMAT_UNSPECIFIED;
}

}  // namespace vscan::client
