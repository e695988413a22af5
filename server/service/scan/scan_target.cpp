#include "service/scan/scan_target.h"

#include <cstdio>

#include "service/robot/robot_links.h"

namespace vscan::service {
namespace {

// Exact joint values: a target cached for one configuration is never reused for another.
std::string ConfigurationKey(const std::string& mount_id, const Eigen::VectorXd& q) {
  std::string key = mount_id + "=";
  char value[32];
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    std::snprintf(value, sizeof(value), i ? ",%a" : "%a", q[i]);
    key += value;
  }
  return key + ";";
}

}  // namespace

StatusOr<scenes::ScanTarget> PrepareScanTarget(ServiceContext& context, const ScanPlan& plan) {
  ASSIGN_OR_RETURN(scenes::ScanTarget base, context.registry.PrepareScan(plan.scene_id, plan.table_angle_deg));
  ASSIGN_OR_RETURN(const auto mounts, SceneMounts(context.robots, plan.scene_id));
  std::vector<raycast::SceneInstance> links;
  std::string key;
  for (const store::MountRecord& record : mounts) {
    if (!record.links_visible) continue;
    ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, context.robots.Mount(record.mount_id));
    ASSIGN_OR_RETURN(const auto geometry,
                     context.robots.Links(record.robot_id, LinkMeshImporter(context.registry)));
    // The carrying robot stands where the scan put it; other mounts stand at home.
    const bool carrying = plan.robot && plan.robot->mount_id == record.mount_id;
    const Eigen::VectorXd q = carrying ? plan.robot->achieved_joint_positions : HomePositions(*mounted.chain);
    key += ConfigurationKey(record.mount_id, q);
    const std::vector<Pose3> base_from_link = robot_registry::LinkPoses(*geometry, q);
    for (size_t i = 0; i < geometry->names.size() && i < robot_registry::kMaxVisibleLinks; ++i) {
      const Pose3 world_from_link = mounted.placement.frame_from_base * base_from_link[i];
      for (const robot_registry::LinkShape& shape : geometry->visual[i]) {
        links.push_back({shape.mesh, world_from_link * shape.link_from_shape, 1.0,
                         robot_registry::LinkInstanceId(record.mount_id, i)});
      }
    }
  }
  if (key.empty()) return base;
  return context.registry.WithExtraInstances(base, key, std::move(links));
}

}  // namespace vscan::service
