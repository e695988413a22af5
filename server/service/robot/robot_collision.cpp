#include "service/robot/robot_collision.h"

#include "service/robot/robot_links.h"
#include "robot/forward_kinematics.h"
#include "robot_registry/link_collision.h"

namespace vscan::service {
namespace {

Pose3 ToPose(const Eigen::Matrix4d& m) {
  Pose3 pose = Pose3::Identity();
  pose.matrix() = m;
  return pose;
}

// Scene objects, and the links of the scene's other mounts at their home positions.
StatusOr<std::vector<robot_registry::Obstacle>> Obstacles(ServiceContext& context, const store::MountRecord& moving,
                                                         double table_angle_deg) {
  std::vector<robot_registry::Obstacle> out;
  ASSIGN_OR_RETURN(const scenes::ScanTarget scene, context.registry.PrepareScan(moving.scene_id, table_angle_deg));
  for (const store::ObjectRecord& object : scene.scene.objects) {
    robot_registry::Obstacle obstacle{"object '" + object.object_id + "' (" + object.label + ")", {}};
    for (const raycast::SceneInstance& instance : *scene.instances) {
      if (instance.instance_id != object.instance_id) continue;
      obstacle.meshes.push_back(
          {instance.mesh, instance.world_from_object, Eigen::Vector3d::Constant(instance.scale)});
    }
    out.push_back(std::move(obstacle));
  }
  ASSIGN_OR_RETURN(const auto mounts, SceneMounts(context.robots, moving.scene_id));
  for (const store::MountRecord& other : mounts) {
    if (other.mount_id == moving.mount_id) continue;
    ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, context.robots.Mount(other.mount_id));
    ASSIGN_OR_RETURN(const auto links, context.robots.Links(other.robot_id, LinkMeshImporter(context.registry)));
    const std::vector<Pose3> base_from_link = robot_registry::LinkPoses(*links, HomePositions(*mounted.chain));
    for (size_t i = 0; i < links->names.size(); ++i) {
      robot_registry::Obstacle obstacle{"link '" + links->names[i] + "' of mount '" + other.mount_id + "'", {}};
      for (const robot_registry::LinkShape& shape : links->collision[i]) {
        obstacle.meshes.push_back(
            {shape.mesh, mounted.placement.frame_from_base * base_from_link[i] * shape.link_from_shape});
      }
      out.push_back(std::move(obstacle));
    }
  }
  return out;
}

}  // namespace

StatusOr<std::optional<std::string>> FindRobotCollision(ServiceContext& context, const std::string& mount_id,
                                                        const Eigen::VectorXd& joint_positions,
                                                        double table_angle_deg) {
  ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, context.robots.Mount(mount_id));
  RETURN_IF_ERROR(robot::ValidateJointPositions(*mounted.chain, joint_positions));
  ASSIGN_OR_RETURN(const auto links, context.robots.Links(mounted.mount.robot_id, LinkMeshImporter(context.registry)));
  ASSIGN_OR_RETURN(const auto obstacles, Obstacles(context, mounted.mount, table_angle_deg));
  return robot_registry::FindLinkContact(*links, links->allowed_contacts, ToPose(mounted.mount.base_pose),
                                         joint_positions, obstacles, context.shapes);
}

}  // namespace vscan::service
