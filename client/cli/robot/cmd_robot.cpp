#include "session/commands.h"
#include "robot/robot_commands.h"
#include "robot/robot_format.h"
#include "session/uploads.h"

namespace vscan::cli {
namespace {

struct RobotUploadArgs {
  std::string path;
  client::RobotUploadOptions options;
};

int RunRobotUpload(Context& ctx, RobotUploadArgs args) {
  v1::Robot robot;
  if (const int rc = UploadRobot(ctx, args.path, args.options, "--urdf", &robot); rc != kExitOk) return rc;
  if (ctx.json()) ctx.EmitJson(ToJson(robot));
  ctx.Done("uploaded robot " + Describe(robot), robot.robot_id());
  for (const auto& warning : robot.warnings()) ctx.Say("warning: " + warning);
  return kExitOk;
}

void AddRobotUpload(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<RobotUploadArgs>();
  auto* cmd = group.add_subcommand("upload", "Upload a URDF robot: a directory (the bundle) or a single URDF file");
  cmd->add_option("DIR_OR_URDF", args->path, "Bundle directory (paths relative to it) or URDF file")->required();
  cmd->add_option("--urdf", args->options.urdf_path, "Path of the URDF inside the directory (default: the only .urdf)");
  cmd->add_option("--base", args->options.base_link, "Base link of the chain (default: the URDF's root)");
  cmd->add_option("--tip", args->options.tip_link, "Tip link of the chain (default: the deepest link)");
  cmd->add_option("--name", args->options.name, "Robot name (default: the URDF's)");
  OnRun(cmd, ctx, [&ctx, args] { return RunRobotUpload(ctx, *args); });
}

void AddRobotList(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("list", "List robots");
  OnRun(cmd, ctx, [&ctx]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto robots = client->ListRobots();
    if (!robots.ok()) return ctx.ServerError(robots.status());
    if (ctx.json()) {
      v1::ListRobotsResponse all;
      for (const auto& r : *robots) *all.add_robots() = r;
      ctx.EmitJson(ToJson(all));
      return kExitOk;
    }
    for (const auto& r : *robots) ctx.Print(ctx.quiet() ? r.robot_id() : Describe(r));
    return kExitOk;
  });
}

void AddRobotGet(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("get", "Show a robot: its chain, joints and warnings");
  auto id = std::make_shared<std::string>();
  cmd->add_option("ROBOT", *id, "Robot id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto robot = client->GetRobot(*id);
    if (!robot.ok()) return ctx.ServerError(robot.status());
    if (ctx.json()) {
      ctx.EmitJson(ToJson(*robot));
      return kExitOk;
    }
    ctx.Print("robot " + Describe(*robot));
    ctx.Print("urdf: " + robot->urdf_path() + " (" + std::to_string(robot->file_count()) + " files, " +
              std::to_string(robot->bundle_bytes()) + " bytes)");
    for (int i = 0; i < robot->joints_size(); ++i) {
      ctx.Print("joint " + std::to_string(i) + ": " + Describe(robot->joints(i)));
    }
    for (const auto& warning : robot->warnings()) ctx.Print("warning: " + warning);
    return kExitOk;
  });
}

void AddRobotDelete(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("delete", "Delete a robot (it must not be mounted)");
  auto id = std::make_shared<std::string>();
  cmd->add_option("ROBOT", *id, "Robot id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const Status status = client->DeleteRobot(*id);
    if (!status.ok()) return ctx.ServerError(status);
    if (ctx.json()) ctx.EmitJson("{\"robotId\":" + JsonQuote(*id) + ",\"deleted\":true}");
    ctx.Done("deleted robot " + *id, "");
    return kExitOk;
  });
}

}  // namespace

void AddRobotCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("robot", "URDF robots: upload, kinematics, mounting in scenes");
  group->require_subcommand(1);
  AddRobotUpload(*group, ctx);
  AddRobotList(*group, ctx);
  AddRobotGet(*group, ctx);
  AddRobotDelete(*group, ctx);
  AddRobotKinematicsCommands(*group, ctx);
  AddRobotMountCommands(*group, ctx);
}

}  // namespace vscan::cli
