// `vscan robot fk|ik|mount|unmount|mounts`.

#include "session/args.h"
#include "robot/robot_args.h"
#include "robot/robot_commands.h"
#include "robot/robot_format.h"
#include "session/commands.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

struct MountArgs {
  std::string scene_id;
  std::string robot_id;
  PoseArgs base;
  PoseArgs tool;
  std::string encoder_sigma;
  bool links_visible = false;
};

int RunFk(Context& ctx, const std::string& robot_id, const std::string& joints) {
  const auto q = ParseNumberList(joints, "JOINTS");
  if (!q.ok()) return ctx.UsageError(q.status().message());
  v1::ForwardKinematicsRequest request;
  request.set_robot_id(robot_id);
  for (double v : *q) request.add_joint_positions(v);
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = client->ForwardKinematics(request);
  if (!response.ok()) return ctx.ServerError(response.status());
  if (ctx.json()) {
    ctx.EmitJson(ToJson(*response));
    return kExitOk;
  }
  ctx.Print("tool: " + DescribeMatrix(response->tool_pose()));
  if (!ctx.quiet()) {
    for (const auto& link : response->link_poses()) ctx.Print("  " + link.link() + ": " + DescribeMatrix(link.pose()));
  }
  return kExitOk;
}

int RunIk(Context& ctx, const IkArgs& args) {
  const auto request = BuildIkRequest(args);
  if (!request.ok()) return ctx.UsageError(request.status().message());
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = client->InverseKinematics(*request);
  if (!response.ok()) return ctx.ServerError(response.status());
  if (ctx.json()) {
    ctx.EmitJson(ToJson(*response));
    return kExitOk;
  }
  if (ctx.quiet()) {
    ctx.Print(JoinNumbers(response->joint_positions()));
    return kExitOk;
  }
  ctx.Print(response->reached()
                ? "reached"
                : "not reached: the nearest configuration misses by " + FormatNumber(response->miss_distance()) + " m");
  ctx.Print("joints: " + JoinNumbers(response->joint_positions()));
  ctx.Print("tool: " + DescribeMatrix(response->tool_pose()));
  ctx.Print("errors: " + FormatNumber(response->position_error()) + " m, " +
            FormatNumber(response->orientation_error_rad()) + " rad; solved in " + FormatNumber(response->solve_ms()) +
            " ms");
  return kExitOk;
}

StatusOr<v1::MountRobotRequest> BuildMountRequest(const MountArgs& args) {
  v1::MountRobotRequest request;
  request.set_scene_id(args.scene_id);
  request.set_robot_id(args.robot_id);
  ASSIGN_OR_RETURN(const PoseParts base, ParsePoseArgs(args.base));
  if (!base.empty()) *request.mutable_base_pose() = PoseToProto(ApplyPoseParts(base, Pose3::Identity()));
  ASSIGN_OR_RETURN(const PoseParts tool_parts, ParsePoseArgs(args.tool));
  if (!tool_parts.empty()) *request.mutable_tool_offset() = PoseToProto(ApplyPoseParts(tool_parts, Pose3::Identity()));
  if (!args.encoder_sigma.empty()) {
    ASSIGN_OR_RETURN(const auto sigma, ParseNumberList(args.encoder_sigma, "--encoder-sigma"));
    for (double s : sigma) request.add_encoder_sigma(s);
  }
  request.set_links_visible(args.links_visible);
  return request;
}

int RunMount(Context& ctx, const MountArgs& args) {
  const auto request = BuildMountRequest(args);
  if (!request.ok()) return ctx.UsageError(request.status().message());
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = client->MountRobot(*request);
  if (!response.ok()) return ctx.ServerError(response.status());
  if (ctx.json()) ctx.EmitJson(ToJson(*response));
  ctx.Done("mounted " + Describe(response->mount()) + "; scene revision " + std::to_string(response->revision()),
           response->mount_id());
  return kExitOk;
}

void AddFk(CLI::App& group, Context& ctx) {
  auto robot = std::make_shared<std::string>();
  auto joints = std::make_shared<std::string>();
  auto* cmd = group.add_subcommand("fk", "Forward kinematics: the tool pose at joint positions (base frame)");
  cmd->add_option("ROBOT", *robot, "Robot id")->required();
  cmd->add_option("JOINTS", *joints, "Joint positions q1,q2,... (radians, metres for prismatic joints)")->required();
  OnRun(cmd, ctx, [&ctx, robot, joints] { return RunFk(ctx, *robot, *joints); });
}

void AddIk(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<IkArgs>();
  auto* cmd = group.add_subcommand("ik", "Inverse kinematics: joint positions that put the tool at a goal");
  cmd->add_option("ROBOT", args->robot_id, "Robot id")->required();
  cmd->add_option("--position", args->position, "Tool position x,y,z in metres")->required();
  auto* quat = cmd->add_option("--quat", args->quat, "Tool orientation w,x,y,z (a full pose goal)");
  auto* look = cmd->add_option("--look-at", args->look_at, "Point x,y,z for the tool's z axis to look at");
  quat->excludes(look);
  cmd->add_option("--method", args->method, "default or gradient (the paper's gradient descent)")
      ->capture_default_str();
  cmd->add_option("--mount", args->mount_id, "Goal in world coordinates of this mount of the robot");
  cmd->add_option("--seed", args->seed, "Starting joint positions q1,q2,... (default: mid-range)");
  cmd->add_option("--tolerance", args->tolerance, "Position tolerance in metres (default 1e-5)");
  cmd->add_option("--timeout-ms", args->timeout_ms, "Solver time budget in milliseconds (default 50)");
  cmd->add_flag("--partial", args->allow_partial, "Print the nearest configuration when the goal is out of reach");
  cmd->add_flag("--avoid-collisions", args->avoid_collisions,
                "Only accept a solution whose arm is clear of the mount's scene (needs --mount)");
  OnRun(cmd, ctx, [&ctx, args] { return RunIk(ctx, *args); });
}

void AddMount(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<MountArgs>();
  auto* cmd = group.add_subcommand("mount", "Place a robot in a scene, with a tool offset for the scanner");
  cmd->add_option("SCENE", args->scene_id, "Scene id")->required();
  cmd->add_option("ROBOT", args->robot_id, "Robot id")->required();
  auto* position = cmd->add_option("--position", args->base.position, "Base position x,y,z in metres");
  auto* rpy = cmd->add_option("--rpy", args->base.rpy, "Base roll,pitch,yaw in degrees, applied as Rz*Ry*Rx");
  auto* matrix = cmd->add_option("--matrix", args->base.matrix, "world_from_base, 16 values row-major");
  matrix->excludes(position)->excludes(rpy);
  cmd->add_option("--tool-position", args->tool.position, "tip_from_sensor translation x,y,z in metres");
  cmd->add_option("--tool-rpy", args->tool.rpy, "tip_from_sensor roll,pitch,yaw in degrees");
  cmd->add_option("--encoder-sigma", args->encoder_sigma,
                  "Encoder noise: one sigma for all joints, or one per joint (radians or metres)");
  cmd->add_flag("--links-visible", args->links_visible, "The robot's links appear in scans of the scene");
  OnRun(cmd, ctx, [&ctx, args] { return RunMount(ctx, *args); });
}

void AddUnmount(CLI::App& group, Context& ctx) {
  auto id = std::make_shared<std::string>();
  auto* cmd = group.add_subcommand("unmount", "Remove a robot's mount from its scene");
  cmd->add_option("MOUNT", *id, "Mount id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto revision = client->UnmountRobot(*id);
    if (!revision.ok()) return ctx.ServerError(revision.status());
    if (ctx.json()) {
      v1::UnmountRobotResponse response;
      response.set_revision(*revision);
      ctx.EmitJson(ToJson(response));
    }
    ctx.Done("unmounted " + *id + "; scene revision " + std::to_string(*revision), "");
    return kExitOk;
  });
}

void AddMounts(CLI::App& group, Context& ctx) {
  auto scene = std::make_shared<std::string>();
  auto* cmd = group.add_subcommand("mounts", "List mounts (of one scene when given)");
  cmd->add_option("SCENE", *scene, "Scene id");
  OnRun(cmd, ctx, [&ctx, scene]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto mounts = client->ListMounts(*scene);
    if (!mounts.ok()) return ctx.ServerError(mounts.status());
    if (ctx.json()) {
      v1::ListMountsResponse all;
      for (const auto& m : *mounts) *all.add_mounts() = m;
      ctx.EmitJson(ToJson(all));
      return kExitOk;
    }
    for (const auto& m : *mounts) ctx.Print(ctx.quiet() ? m.mount_id() : Describe(m));
    return kExitOk;
  });
}

}  // namespace

void AddRobotKinematicsCommands(CLI::App& group, Context& ctx) {
  AddFk(group, ctx);
  AddIk(group, ctx);
}

void AddRobotMountCommands(CLI::App& group, Context& ctx) {
  AddMount(group, ctx);
  AddUnmount(group, ctx);
  AddMounts(group, ctx);
}

}  // namespace vscan::cli
