#include "service/robot/robot_links.h"

#include <algorithm>
#include <cctype>

namespace vscan::service {
namespace {

constexpr int kMountPage = 1000;

std::string Extension(std::string_view path) {
  const size_t dot = path.rfind('.');
  if (dot == std::string_view::npos || path.find('/', dot) != std::string_view::npos) return "";
  std::string ext(path.substr(dot + 1));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

robot_registry::LinkMeshImporter LinkMeshImporter(scenes::SceneRegistry& registry) {
  return [&registry](std::string_view bytes, std::string_view path) -> StatusOr<TriangleMesh> {
    const std::string ext = Extension(path);
    geometry::MeshFileFormat format;
    if (ext == "stl") {
      format = geometry::MeshFileFormat::kStl;
    } else if (ext == "obj") {
      format = geometry::MeshFileFormat::kObj;
    } else if (ext == "ply") {
      format = geometry::MeshFileFormat::kPly;
    } else {
      return Unimplemented("mesh format '." + ext + "' is not supported for link geometry (STL, OBJ, PLY)");
    }
    return registry.ImportUserMesh(bytes, format);
  };
}

StatusOr<std::vector<store::MountRecord>> SceneMounts(robot_registry::RobotRegistry& robots,
                                                       const std::string& scene_id) {
  std::vector<store::MountRecord> all;
  std::string after;
  while (true) {
    ASSIGN_OR_RETURN(auto page, robots.catalogue().ListMounts(scene_id, after, kMountPage));
    const bool more = static_cast<int>(page.size()) == kMountPage;
    for (auto& mount : page) all.push_back(std::move(mount));
    if (!more) return all;
    after = all.back().mount_id;
  }
}

Eigen::VectorXd HomePositions(const robot::KinematicChain& chain) {
  return robot::ClampToLimits(chain, Eigen::VectorXd::Zero(chain.dof()));
}

}  // namespace vscan::service
