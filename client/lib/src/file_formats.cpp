#include <algorithm>
#include <cctype>
#include <filesystem>

#include "vscan/client/types.h"

namespace vscan::client {

v1::MeshFormat MeshFormatFromPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".ply") return v1::MESH_FORMAT_PLY;
  if (ext == ".obj") return v1::MESH_FORMAT_OBJ;
  if (ext == ".stl") return v1::MESH_FORMAT_STL;
  return v1::MESH_FORMAT_UNSPECIFIED;
}

}  // namespace vscan::client
