#pragma once
// A robot upload: one URDF plus the meshes it references, checked and parsed.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "robot/bundle_paths.h"
#include "vscan/common/status.h"

namespace urdf {
class ModelInterface;
}

namespace vscan::robot {

// One uploaded file; path is relative to the bundle root.
struct BundleFile {
  std::string path;
  std::string bytes;
};

struct BundleLimits {
  uint64_t max_total_bytes = 256ull << 20;
  uint32_t max_files = 1024;
};

// A mesh named by a link's visual or collision geometry.
struct MeshReference {
  std::string link;
  std::string role;  // "visual" or "collision"
  int index = 0;     // position among the link's visuals or collisions
  std::string uri;   // as written in the URDF
  std::string bundle_path;  // normalised bundle path; empty when the bundle lacks the file
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};

struct UrdfBundle {
  std::string urdf_path;  // normalised
  std::shared_ptr<const urdf::ModelInterface> model;
  BundleFiles files;
  std::vector<MeshReference> meshes;
  std::vector<std::string> warnings;  // one per missing mesh; kinematics work regardless
};

// Normalises every path (InvalidArgument naming files[i].path on an escape or a duplicate),
// enforces limits (ResourceExhausted), parses the URDF (InvalidArgument "urdf: ..."), checks that
// its joints form a tree (CheckUrdfTree) and its geometry is bounded (CheckUrdfBounds), and
// resolves mesh references as ResolveMeshReference documents; escaping references are InvalidArgument.
StatusOr<UrdfBundle> LoadUrdfBundle(std::string_view urdf_path, std::vector<BundleFile> files,
                                    const BundleLimits& limits = {});

}  // namespace vscan::robot
