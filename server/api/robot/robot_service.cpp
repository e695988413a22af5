#include "api/robot/robot_service.h"

#include <cmath>

#include "api/robot/robot_convert.h"
#include "api/transport/unary.h"
#include "api/transport/validate.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

StatusOr<std::vector<double>> EncoderSigma(const google::protobuf::RepeatedField<double>& sigma) {
  std::vector<double> out;
  for (int i = 0; i < sigma.size(); ++i) {
    if (!std::isfinite(sigma[i]) || sigma[i] < 0) {
      return InvalidArgument("encoder_sigma[" + std::to_string(i) + "]: must be finite and not negative");
    }
    out.push_back(sigma[i]);
  }
  return out;
}

StatusOr<store::MountRecord> MountFromRequest(const v1::MountRobotRequest& request) {
  RETURN_IF_ERROR(RequireId(request.scene_id(), "scene_id"));
  RETURN_IF_ERROR(RequireId(request.robot_id(), "robot_id"));
  store::MountRecord mount;
  mount.scene_id = request.scene_id();
  mount.robot_id = request.robot_id();
  if (request.has_base_pose()) {
    ASSIGN_OR_RETURN(const Pose3 base, PoseFromProto(request.base_pose(), "base_pose"));
    mount.base_pose = base.matrix();
  }
  if (request.has_tool_offset()) {
    ASSIGN_OR_RETURN(const Pose3 tool, PoseFromProto(request.tool_offset(), "tool_offset"));
    mount.tool_offset = tool.matrix();
  }
  mount.links_visible = request.links_visible();
  ASSIGN_OR_RETURN(mount.encoder_sigma, EncoderSigma(request.encoder_sigma()));
  return mount;
}

// The mount as the client sees it: with the robot's tool when the mount has none of its own.
Status MountToProto(robot_registry::RobotRegistry& robots, const store::MountRecord& mount, v1::Mount* out) {
  ASSIGN_OR_RETURN(const store::RobotRecord robot, robots.catalogue().GetRobot(mount.robot_id));
  ToProto(mount, robot.tool_offset, out);
  if (mount.links_visible) out->set_link_instance_id_base(robot_registry::LinkInstanceIdBase(mount.mount_id));
  return Status::Ok();
}

}  // namespace

grpc::ServerUnaryReactor* RobotService::GetRobot(grpc::CallbackServerContext* ctx, const v1::GetRobotRequest* request,
                                                 v1::GetRobotResponse* response) {
  return RunUnary(ctx, context_.options.token, "GetRobot", [&]() -> Status {
    RETURN_IF_ERROR(RequireId(request->robot_id(), "robot_id"));
    ASSIGN_OR_RETURN(const auto robot, context_.robots.catalogue().GetRobot(request->robot_id()));
    ToProto(robot, response->mutable_robot());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* RobotService::ListRobots(grpc::CallbackServerContext* ctx,
                                                   const v1::ListRobotsRequest* request,
                                                   v1::ListRobotsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListRobots", [&]() -> Status {
    ASSIGN_OR_RETURN(int limit, PageSize(request->page_size(), context_.options.limits.max_page_size));
    RETURN_IF_ERROR(CheckPageToken(request->page_token(), "rbt_"));
    ASSIGN_OR_RETURN(auto robots, context_.robots.catalogue().ListRobots(request->page_token(), limit + 1));
    const bool more = static_cast<int>(robots.size()) > limit;
    if (more) robots.resize(limit);
    for (const auto& robot : robots) ToProto(robot, response->add_robots());
    if (more) response->set_next_page_token(robots.back().robot_id);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* RobotService::DeleteRobot(grpc::CallbackServerContext* ctx,
                                                    const v1::DeleteRobotRequest* request, v1::DeleteRobotResponse*) {
  return RunBlockingUnary(ctx, context_.options.token, "DeleteRobot", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->robot_id(), "robot_id"));
    return context_.robots.DeleteRobot(request->robot_id());
  });
}

grpc::ServerUnaryReactor* RobotService::MountRobot(grpc::CallbackServerContext* ctx,
                                                   const v1::MountRobotRequest* request,
                                                   v1::MountRobotResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "MountRobot", context_.call_workers, [=, this]() -> Status {
    ASSIGN_OR_RETURN(store::MountRecord mount, MountFromRequest(*request));
    ASSIGN_OR_RETURN(const auto added, context_.robots.AddMount(std::move(mount)));
    response->set_mount_id(added.first.mount_id);
    response->set_revision(added.second);
    return MountToProto(context_.robots, added.first, response->mutable_mount());
  });
}

grpc::ServerUnaryReactor* RobotService::GetMount(grpc::CallbackServerContext* ctx, const v1::GetMountRequest* request,
                                                 v1::GetMountResponse* response) {
  return RunUnary(ctx, context_.options.token, "GetMount", [&]() -> Status {
    RETURN_IF_ERROR(RequireId(request->mount_id(), "mount_id"));
    ASSIGN_OR_RETURN(const auto mount, context_.robots.catalogue().GetMount(request->mount_id()));
    return MountToProto(context_.robots, mount, response->mutable_mount());
  });
}

grpc::ServerUnaryReactor* RobotService::ListMounts(grpc::CallbackServerContext* ctx,
                                                   const v1::ListMountsRequest* request,
                                                   v1::ListMountsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListMounts", [&]() -> Status {
    if (!request->scene_id().empty()) RETURN_IF_ERROR(RequireId(request->scene_id(), "scene_id"));
    ASSIGN_OR_RETURN(int limit, PageSize(request->page_size(), context_.options.limits.max_page_size));
    RETURN_IF_ERROR(CheckPageToken(request->page_token(), "mnt_"));
    ASSIGN_OR_RETURN(auto mounts,
                     context_.robots.catalogue().ListMounts(request->scene_id(), request->page_token(), limit + 1));
    const bool more = static_cast<int>(mounts.size()) > limit;
    if (more) mounts.resize(limit);
    for (const auto& mount : mounts) RETURN_IF_ERROR(MountToProto(context_.robots, mount, response->add_mounts()));
    if (more) response->set_next_page_token(mounts.back().mount_id);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* RobotService::UnmountRobot(grpc::CallbackServerContext* ctx,
                                                     const v1::UnmountRobotRequest* request,
                                                     v1::UnmountRobotResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "UnmountRobot", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->mount_id(), "mount_id"));
    ASSIGN_OR_RETURN(const uint64_t revision, context_.robots.catalogue().DeleteMount(request->mount_id()));
    response->set_revision(revision);
    return Status::Ok();
  });
}

}  // namespace vscan::api
