#include "web/web_robots.h"

#include <charconv>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "robot/forward_kinematics.h"
#include "robot_registry/robot_registry.h"
#include "service/robot/robot_links.h"
#include "web/web_encode.h"

namespace vscan::web {
namespace {

// "q1,q2,..." as exactly dof finite numbers within the chain's limits.
StatusOr<Eigen::VectorXd> ParseJoints(std::string_view text, const robot::KinematicChain& chain) {
  std::vector<std::string_view> items;
  while (items.size() <= static_cast<size_t>(chain.dof())) {
    const size_t comma = text.find(',');
    items.push_back(text.substr(0, comma));
    if (comma == std::string_view::npos) break;
    text = text.substr(comma + 1);
  }
  if (items.size() != static_cast<size_t>(chain.dof())) {
    return InvalidArgument(fmt::format("joints: give {} comma-separated positions, one per joint", chain.dof()));
  }
  Eigen::VectorXd q(chain.dof());
  for (int i = 0; i < chain.dof(); ++i) {
    const std::string_view item = items[i];
    double value = 0;
    const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), value);
    if (item.empty() || error != std::errc() || end != item.data() + item.size() || !std::isfinite(value)) {
      return InvalidArgument(fmt::format("joints[{}]: '{}' is not a finite number", i, item));
    }
    q[i] = value;
  }
  RETURN_IF_ERROR(robot::ValidateJointPositions(chain, q, "joints"));
  return q;
}

}  // namespace

WebReply ServeMounts(const WebSources& sources, const WebRequest& request) {
  if (!sources.robots || !sources.scenes) return TextReply(404, "mounts are not served");
  const auto& segments = request.segments;
  const bool shape = segments.size() == 4 && segments[2] == "shapes";
  if (!(segments.size() == 2 || shape) || !IsId(segments[1])) return TextReply(404, "no such mount resource");
  const std::string mount_id(segments[1]);
  auto mounted = sources.robots->Mount(mount_id);
  if (!mounted.ok()) return FromStatus(mounted.status());
  auto links = sources.robots->Links(mounted->mount.robot_id, service::LinkMeshImporter(*sources.scenes));
  if (!links.ok()) return FromStatus(links.status());
  std::vector<MountShape> shapes;
  Eigen::VectorXd q = service::HomePositions(*mounted->chain);
  if (const std::optional<std::string> joints = request.Query("joints"); joints && !shape) {
    auto parsed = ParseJoints(*joints, *mounted->chain);
    if (!parsed.ok()) return FromStatus(parsed.status());
    q = *parsed;
  }
  const Pose3& world_from_base = mounted->placement.frame_from_base;
  const std::vector<Pose3> base_from_link = robot_registry::LinkPoses(**links, q);
  for (size_t i = 0; i < (*links)->names.size(); ++i) {
    for (const robot_registry::LinkShape& link_shape : (*links)->visual[i]) {
      shapes.push_back({(*links)->names[i], link_shape.mesh.get(),
                        (world_from_base * base_from_link[i] * link_shape.link_from_shape).matrix()});
    }
  }
  if (shape) {
    size_t index = 0;
    const auto [end, error] = std::from_chars(segments[3].data(), segments[3].data() + segments[3].size(), index);
    if (error != std::errc() || end != segments[3].data() + segments[3].size() || index >= shapes.size()) {
      return TextReply(404, fmt::format("mount {} has no shape '{}'", mount_id, segments[3]));
    }
    return {200, kBinaryType, MeshBinary(*shapes[index].mesh), {}};
  }
  auto base_from_tool = robot::ForwardKinematics(*mounted->chain, q);
  if (!base_from_tool.ok()) return FromStatus(base_from_tool.status());
  MountPose pose{mounted->mount, q, (world_from_base * *base_from_tool).matrix()};
  return JsonReply(MountJson(pose, shapes));
}

}  // namespace vscan::web
