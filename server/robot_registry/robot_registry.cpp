#include "robot_registry/robot_registry.h"

#include <spdlog/spdlog.h>

#include "robot_registry/bundle_codec.h"
#include "robot_registry/link_collision.h"
#include "store/blob_gc.h"

namespace vscan::robot_registry {
namespace {

Pose3 ToPose(const Eigen::Matrix4d& m) {
  Pose3 pose = Pose3::Identity();
  pose.matrix() = m;
  return pose;
}

}  // namespace

RobotRegistry::RobotRegistry(store::RobotCatalogue& catalogue, store::BlobStore& blobs, uint64_t max_bundle_bytes,
                             size_t cache_entries)
    : RobotRegistry(catalogue, blobs, robot::BundleLimits{max_bundle_bytes, robot::BundleLimits{}.max_files},
                    cache_entries) {}

RobotRegistry::RobotRegistry(store::RobotCatalogue& catalogue, store::BlobStore& blobs, robot::BundleLimits limits,
                             size_t cache_entries)
    : catalogue_(catalogue), blobs_(blobs), limits_(limits), cache_entries_(cache_entries) {}

StatusOr<store::RobotRecord> RobotRegistry::AddRobot(RobotUpload upload) {
  ASSIGN_OR_RETURN(ImportedRobot imported, ImportRobot(std::move(upload), limits_));
  store::RobotRecord record;
  {
    std::lock_guard lock(store_mutex_);
    // A full disk or a failing store names the robot it was storing.
    const std::string storing = "storing robot '" + imported.record.name + "': ";
    auto pin = blobs_.PutPinned(imported.bundle_blob);
    if (!pin.ok()) return Status(pin.status().code(), storing + pin.status().message());
    imported.record.bundle_sha256 = pin->sha256();
    auto inserted = catalogue_.InsertRobot(std::move(imported.record));
    if (!inserted.ok()) return Status(inserted.status().code(), storing + inserted.status().message());
    record = std::move(inserted).value();
  }
  std::lock_guard lock(cache_mutex_);
  if (chains_.size() >= cache_entries_) chains_.erase(chains_.begin());
  chains_[record.robot_id] = imported.chain;
  return record;
}

Status RobotRegistry::DeleteRobot(const std::string& robot_id) {
  {
    std::lock_guard lock(store_mutex_);
    ASSIGN_OR_RETURN(auto deleted, catalogue_.DeleteRobot(robot_id));
    // The robot is gone either way; a blob left behind only costs disk space.
    const auto collected = store::CollectBlobs(catalogue_.database(), blobs_, {deleted.first});
    if (!collected.ok()) {
      spdlog::warn("robot {}: bundle blob not removed: {}", robot_id, collected.status().ToString());
    }
  }
  std::lock_guard lock(cache_mutex_);
  chains_.erase(robot_id);
  links_.erase(robot_id);
  return Status::Ok();
}

StatusOr<std::shared_ptr<const robot::KinematicChain>> RobotRegistry::Chain(const std::string& robot_id) {
  {
    std::lock_guard lock(cache_mutex_);
    if (auto it = chains_.find(robot_id); it != chains_.end()) return it->second;
  }
  ASSIGN_OR_RETURN(const store::RobotRecord record, catalogue_.GetRobot(robot_id));
  ASSIGN_OR_RETURN(const std::string blob, blobs_.Get(record.bundle_sha256));
  ASSIGN_OR_RETURN(auto files, DecodeBundle(blob));
  ASSIGN_OR_RETURN(auto chain, LoadStoredChain(record, std::move(files)));
  std::lock_guard lock(cache_mutex_);
  if (chains_.size() >= cache_entries_) chains_.erase(chains_.begin());
  chains_[robot_id] = chain;
  return chain;
}

StatusOr<std::pair<store::MountRecord, uint64_t>> RobotRegistry::AddMount(store::MountRecord mount) {
  ASSIGN_OR_RETURN(auto chain, Chain(mount.robot_id));
  const size_t dof = static_cast<size_t>(chain->dof());
  if (mount.encoder_sigma.size() == 1 && dof > 1) mount.encoder_sigma.assign(dof, mount.encoder_sigma.front());
  if (!mount.encoder_sigma.empty() && mount.encoder_sigma.size() != dof) {
    return InvalidArgument("encoder_sigma: expected 1 or " + std::to_string(dof) + " values (one per joint of robot '" +
                           mount.robot_id + "'), got " + std::to_string(mount.encoder_sigma.size()));
  }
  return catalogue_.InsertMount(std::move(mount));
}

StatusOr<MountedRobot> RobotRegistry::Mount(const std::string& mount_id) {
  MountedRobot out;
  ASSIGN_OR_RETURN(out.mount, catalogue_.GetMount(mount_id));
  ASSIGN_OR_RETURN(out.chain, Chain(out.mount.robot_id));
  if (out.mount.tool_offset) {
    out.chain = std::make_shared<const robot::KinematicChain>(out.chain->WithTool(ToPose(*out.mount.tool_offset)));
  }
  out.placement.frame_from_base = ToPose(out.mount.base_pose);
  out.placement.encoder_sigma = Eigen::Map<const Eigen::VectorXd>(
      out.mount.encoder_sigma.data(), static_cast<Eigen::Index>(out.mount.encoder_sigma.size()));
  return out;
}

StatusOr<std::shared_ptr<const RobotLinks>> RobotRegistry::Links(const std::string& robot_id,
                                                                 const LinkMeshImporter& import) {
  {
    std::lock_guard lock(cache_mutex_);
    if (auto it = links_.find(robot_id); it != links_.end()) return it->second;
  }
  ASSIGN_OR_RETURN(const store::RobotRecord record, catalogue_.GetRobot(robot_id));
  ASSIGN_OR_RETURN(auto chain, Chain(robot_id));
  ASSIGN_OR_RETURN(const std::string blob, blobs_.Get(record.bundle_sha256));
  ASSIGN_OR_RETURN(auto files, DecodeBundle(blob));
  robot::BundleLimits unlimited;  // checked at upload
  unlimited.max_total_bytes = ~uint64_t{0};
  unlimited.max_files = ~uint32_t{0};
  auto bundle = robot::LoadUrdfBundle(record.urdf_path, std::move(files), unlimited);
  if (!bundle.ok()) return DataLoss("robot '" + robot_id + "': stored bundle: " + bundle.status().message());
  ASSIGN_OR_RETURN(RobotLinks loaded, LoadRobotLinks(*bundle, *chain, import));
  loaded.allowed_contacts = AllowedLinkContacts(loaded, std::make_shared<collision::ShapeCache>());
  for (const std::string& warning : loaded.warnings) spdlog::warn("robot {}: {}", robot_id, warning);
  auto shared = std::make_shared<const RobotLinks>(std::move(loaded));
  std::lock_guard lock(cache_mutex_);
  if (links_.size() >= cache_entries_) links_.erase(links_.begin());
  links_[robot_id] = shared;
  return shared;
}

}  // namespace vscan::robot_registry
