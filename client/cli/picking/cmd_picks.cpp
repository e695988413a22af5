// vscan grasps|picks: a gripper's grasps of a stored mesh, and which parts of a mount's scene the
// robot could pick with it (PickingService).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "picking/gripper_args.h"
#include "picking/pick_report.h"
#include "picking/picking_calls.h"
#include "session/commands.h"

namespace vscan::cli {
namespace {

struct GraspsArgs {
  std::string mesh_id;
  std::optional<double> scale;
  GripperArgs gripper;
  std::optional<uint32_t> max_grasps;
  std::optional<uint64_t> seed;
};

struct PicksArgs {
  std::string mount_id;
  std::vector<std::string> part_ids;
  GripperArgs gripper;
  std::optional<uint32_t> max_grasps;
  std::optional<uint64_t> seed;
  std::optional<double> approach_distance;
  std::optional<double> max_tilt_from_down_deg;
  std::optional<uint32_t> max_reach_checks;
  std::optional<double> body_length;
  std::optional<uint32_t> ik_budget_ms;
};

void SetGraspOptions(const std::optional<uint32_t>& max_grasps, const std::optional<uint64_t>& seed,
                     v1::GraspOptions* options) {
  if (max_grasps) options->set_max_grasps(*max_grasps);
  if (seed) options->set_seed(*seed);
}

int RunGrasps(Context& ctx, const GraspsArgs& args) {
  v1::GenerateGraspsRequest request;
  request.set_mesh_id(args.mesh_id);
  if (args.scale) request.set_scale(*args.scale);
  const auto gripper = BuildGripper(args.gripper);
  if (!gripper.ok()) return ctx.UsageError(gripper.status().message());
  *request.mutable_gripper() = *gripper;
  SetGraspOptions(args.max_grasps, args.seed, request.mutable_options());
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = CallGenerateGrasps(*client, request);
  if (!response.ok()) return ctx.ServerError(response.status());
  if (ctx.json()) {
    ctx.EmitJson(ToJson(*response));
    return kExitOk;
  }
  for (const std::string& line : GraspLines(*response)) ctx.Say(line);
  return kExitOk;
}

int RunPicks(Context& ctx, const PicksArgs& args) {
  v1::CheckPicksRequest request;
  request.set_mount_id(args.mount_id);
  for (const std::string& id : args.part_ids) request.add_part_object_ids(id);
  const auto gripper = BuildGripper(args.gripper);
  if (!gripper.ok()) return ctx.UsageError(gripper.status().message());
  *request.mutable_gripper() = *gripper;
  SetGraspOptions(args.max_grasps, args.seed, request.mutable_grasp_options());
  v1::PickOptions* pick = request.mutable_pick_options();
  if (args.approach_distance) pick->set_approach_distance(*args.approach_distance);
  if (args.max_tilt_from_down_deg) pick->set_max_approach_tilt_deg(*args.max_tilt_from_down_deg);
  if (args.max_reach_checks) pick->set_max_reach_checks(*args.max_reach_checks);
  if (args.body_length) pick->set_body_length(*args.body_length);
  if (args.ik_budget_ms) pick->set_ik_time_budget_ms(*args.ik_budget_ms);
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = CallCheckPicks(*client, request);
  if (!response.ok()) return ctx.ServerError(response.status());
  if (ctx.json()) {
    ctx.EmitJson(ToJson(*response));
    return kExitOk;
  }
  for (const std::string& line : PickLines(*response)) ctx.Say(line);
  return kExitOk;
}

void AddGraspOptions(CLI::App* command, std::optional<uint32_t>& max_grasps, std::optional<uint64_t>& seed) {
  command->add_option("--max-grasps", max_grasps, "At most this many grasps per part, best first (100)");
  command->add_option("--seed", seed, "Seed of the surface sampling (1); the same seed gives the same grasps");
}

}  // namespace

void AddPickingCommands(CLI::App& app, Context& ctx) {
  auto gargs = std::make_shared<GraspsArgs>();
  auto* grasps = app.add_subcommand("grasps", "A suction cup's or parallel jaws' grasps of a stored mesh");
  grasps->add_option("--mesh", gargs->mesh_id, "The mesh id")->required();
  grasps->add_option("--scale", gargs->scale, "Scale on the mesh (1)");
  AddGripperOptions(grasps, gargs->gripper);
  AddGraspOptions(grasps, gargs->max_grasps, gargs->seed);
  OnRun(grasps, ctx, [&ctx, gargs] { return RunGrasps(ctx, *gargs); });

  auto pargs = std::make_shared<PicksArgs>();
  auto* picks = app.add_subcommand(
      "picks", "Which parts of a mount's scene the robot could pick with a gripper on its flange");
  picks->add_option("--mount", pargs->mount_id, "The mount (its tool frame is the gripper's tool centre point)")
      ->required();
  picks->add_option("--part", pargs->part_ids,
                    "A part's object id (repeatable; none: every object labelled <name>#<n>)");
  AddGripperOptions(picks, pargs->gripper);
  AddGraspOptions(picks, pargs->max_grasps, pargs->seed);
  picks->add_option("--approach-distance", pargs->approach_distance,
                    "The pre-grasp stands this far back along the approach, m (0.05)");
  picks->add_option("--max-tilt-from-down", pargs->max_tilt_from_down_deg,
                    "The approach may tilt this far from straight down, degrees (60)");
  picks->add_option("--max-reach-checks", pargs->max_reach_checks,
                    "Grasps per part tried with inverse kinematics, best first (8)");
  picks->add_option("--body-length", pargs->body_length,
                    "The gripper's body behind the tool centre point, m (the mount's tool offset length)");
  picks->add_option("--ik-budget-ms", pargs->ik_budget_ms, "Time per inverse-kinematics solve, ms (20)");
  OnRun(picks, ctx, [&ctx, pargs] { return RunPicks(ctx, *pargs); });
}

}  // namespace vscan::cli
