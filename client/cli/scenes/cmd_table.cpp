#include <cmath>

#include "session/args.h"
#include "session/commands.h"
#include "session/describe.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

struct TableArgs {
  std::string scene_id;
  std::string centre = "0,0,0";
  std::string axis = "0,0,1";
  std::optional<double> angle_deg;
  bool disable = false;
};

int RunSet(Context& ctx, const TableArgs& args) {
  const auto centre = ParseVector3(args.centre, "--centre");
  if (!centre.ok()) return ctx.UsageError(centre.status().message());
  const auto axis = ParseVector3(args.axis, "--axis");
  if (!axis.ok()) return ctx.UsageError(axis.status().message());
  if (axis->norm() == 0) return ctx.UsageError("--axis: must not be the zero vector");
  if (!args.disable && !args.angle_deg) return ctx.UsageError("--angle is required (unless --disable)");
  if (args.angle_deg && !std::isfinite(*args.angle_deg)) return ctx.UsageError("--angle: not a finite number");

  v1::RotaryTable table;
  table.set_enabled(!args.disable);
  *table.mutable_centre() = ToProto(*centre);
  *table.mutable_axis() = ToProto(axis->normalized());
  table.set_angle_deg(args.angle_deg.value_or(0.0));

  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = client->SetRotaryTable(args.scene_id, table);
  if (!response.ok()) return ctx.ServerError(response.status());
  if (ctx.json()) ctx.EmitJson(ToJson(*response));
  ctx.Done("table: " + Describe(response->table()) + "; scene revision " + std::to_string(response->revision()), "");
  return kExitOk;
}

}  // namespace

void AddTableCommand(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("table", "Configure a scene's rotary table");
  group->require_subcommand(1);
  auto args = std::make_shared<TableArgs>();
  auto* set = group->add_subcommand("set", "Set the table's centre, axis and angle");
  set->add_option("SCENE", args->scene_id, "Scene id")->required();
  set->add_option("--centre,--center", args->centre, "Point on the axis x,y,z in metres")->capture_default_str();
  set->add_option("--axis", args->axis, "Rotation axis x,y,z")->capture_default_str();
  set->add_option("--angle", args->angle_deg, "Rotation angle in degrees");
  set->add_flag("--disable", args->disable, "Turn the table off (objects stay at their table-frame pose)");
  OnRun(set, ctx, [&ctx, args] { return RunSet(ctx, *args); });
}

}  // namespace vscan::cli
