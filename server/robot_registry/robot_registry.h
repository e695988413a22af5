#pragma once
// Robots as kinematics needs them: uploads validated and stored durably, chains rebuilt from
// stored bundles and cached by robot id (robots never change), mounts resolved to a chain with
// the mount's tool and its place in the world.

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "robot/chain.h"
#include "robot_registry/arm_kinematics.h"
#include "robot_registry/link_geometry.h"
#include "robot_registry/robot_import.h"
#include "store/blob_store.h"
#include "store/robot_catalogue.h"

namespace vscan::robot_registry {

// A mount with everything needed to move its robot in world coordinates.
struct MountedRobot {
  store::MountRecord mount;
  std::shared_ptr<const robot::KinematicChain> chain;  // the mount's tool on the tip
  Placement placement;                                 // world_from_base; sigma per joint
};

class RobotRegistry {
 public:
  // Bundles larger than max_bundle_bytes (file bytes plus paths) are RESOURCE_EXHAUSTED.
  RobotRegistry(store::RobotCatalogue& catalogue, store::BlobStore& blobs, uint64_t max_bundle_bytes,
                size_t cache_entries = 64);
  // Bundles with more files than limits.max_files are RESOURCE_EXHAUSTED too.
  RobotRegistry(store::RobotCatalogue& catalogue, store::BlobStore& blobs, robot::BundleLimits limits,
                size_t cache_entries = 64);

  store::RobotCatalogue& catalogue() { return catalogue_; }
  uint64_t max_bundle_bytes() const { return limits_.max_total_bytes; }
  uint32_t max_files() const { return limits_.max_files; }

  // Validates, stores the bundle blob durably, then records the robot.
  StatusOr<store::RobotRecord> AddRobot(RobotUpload upload);
  // FAILED_PRECONDITION while mounted; the bundle blob goes when no other robot shares it.
  Status DeleteRobot(const std::string& robot_id);

  // The robot's chain with its own tool offset.
  StatusOr<std::shared_ptr<const robot::KinematicChain>> Chain(const std::string& robot_id);

  // Checks the mount against its robot (sigma count, finite poses), then records it. A single
  // sigma applies to every joint. Returns the mount and the scene's new revision.
  StatusOr<std::pair<store::MountRecord, uint64_t>> AddMount(store::MountRecord mount);
  StatusOr<MountedRobot> Mount(const std::string& mount_id);

  // The robot's link geometry from its stored bundle, mesh files parsed by import; cached by
  // robot id (a robot's bundle never changes).
  StatusOr<std::shared_ptr<const RobotLinks>> Links(const std::string& robot_id, const LinkMeshImporter& import);

 private:
  store::RobotCatalogue& catalogue_;
  store::BlobStore& blobs_;
  robot::BundleLimits limits_;
  size_t cache_entries_;

  // Orders blob writes against blob removals so that a robot never points at a removed bundle.
  std::mutex store_mutex_;
  std::mutex cache_mutex_;
  std::map<std::string, std::shared_ptr<const robot::KinematicChain>> chains_;
  std::map<std::string, std::shared_ptr<const RobotLinks>> links_;
};

}  // namespace vscan::robot_registry
