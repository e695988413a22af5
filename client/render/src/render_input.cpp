#include "vscan/render/render_input.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "geometry/mesh_import.h"
#include "vscan/common/cloud_io.h"

namespace vscan::render {
namespace {

std::string Extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// True when the PLY header declares a face element with at least one face.
StatusOr<bool> PlyHasFaces(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open: " + std::strerror(errno));
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return InvalidArgument(path + ": not a PLY file");
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string word, name;
    size_t count = 0;
    ss >> word;
    if (word == "end_header") return false;
    if (word == "element" && (ss >> name >> count) && name == "face") return count > 0;
  }
  return InvalidArgument(path + ": PLY header has no end_header");
}

StatusOr<TriangleMesh> ReadMesh(const std::string& path, geometry::MeshFileFormat format) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open: " + std::strerror(errno));
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto mesh = geometry::ImportMesh(bytes, format, 1.0);
  if (!mesh.ok()) return Status(mesh.status().code(), path + ": " + mesh.status().message());
  return mesh;
}

template <typename Points>
StatusOr<Bounds> BoundsOf(const Points& points, const std::string& path) {
  Bounds b;
  b.min.setConstant(std::numeric_limits<float>::infinity());
  b.max = -b.min;
  bool any = false;
  for (const Eigen::Vector3f& p : points) {
    if (!p.allFinite()) continue;
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
    any = true;
  }
  if (!any) return InvalidArgument(path + ": nothing to draw (no finite points)");
  return b;
}

}  // namespace

StatusOr<InputKind> InputKindOf(const std::string& path) {
  const std::string ext = Extension(path);
  if (ext == ".pcd") return InputKind::kCloud;
  if (ext == ".obj" || ext == ".stl") return InputKind::kMesh;
  if (ext == ".ply") {
    ASSIGN_OR_RETURN(const bool faces, PlyHasFaces(path));
    return faces ? InputKind::kMesh : InputKind::kCloud;
  }
  return InvalidArgument("INPUT: " + path + ": unknown extension '" + ext + "' (use .ply, .pcd, .obj or .stl)");
}

StatusOr<RenderInput> LoadRenderInput(const std::string& path) {
  RenderInput input;
  ASSIGN_OR_RETURN(input.kind, InputKindOf(path));
  const std::string ext = Extension(path);
  if (input.kind == InputKind::kCloud) {
    ASSIGN_OR_RETURN(input.cloud, ReadCloud(path));
    ASSIGN_OR_RETURN(input.bounds, BoundsOf(input.cloud.positions, path));
  } else {
    const auto format = ext == ".ply"   ? geometry::MeshFileFormat::kPly
                        : ext == ".obj" ? geometry::MeshFileFormat::kObj
                                        : geometry::MeshFileFormat::kStl;
    ASSIGN_OR_RETURN(input.mesh, ReadMesh(path, format));
    ASSIGN_OR_RETURN(input.bounds, BoundsOf(input.mesh.vertices, path));
  }
  return input;
}

}  // namespace vscan::render
