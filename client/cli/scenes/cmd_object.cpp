#include <cmath>

#include "scan/pose_options.h"
#include "scenes/material_option.h"
#include "session/args.h"
#include "session/commands.h"
#include "session/describe.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

struct ObjectArgs {
  std::string scene_id;
  std::string id;  // mesh id for add, object id for move/remove
  PoseArgs pose;
  double scale = 0.0;
  std::string label;
  bool on_table = false;
  std::string material;
  bool clear_material = false;
};

int PrintPlaced(Context& ctx, const std::string& verb, const v1::SceneObject& object, uint64_t revision,
                const google::protobuf::Message& response) {
  if (ctx.json()) ctx.EmitJson(ToJson(response));
  ctx.Done(verb + " object " + Describe(object) + "; scene revision " + std::to_string(revision), object.object_id());
  return kExitOk;
}

int RunAdd(Context& ctx, const ObjectArgs& args) {
  const auto parts = ParsePoseArgs(args.pose);
  if (!parts.ok()) return ctx.UsageError(parts.status().message());
  if (args.scale < 0 || !std::isfinite(args.scale)) return ctx.UsageError("--scale: must be a positive number");
  client::ObjectPlacement placement;
  placement.pose = PoseToProto(ApplyPoseParts(*parts, Pose3::Identity()));
  placement.scale = args.scale;
  placement.label = args.label;
  placement.on_table = args.on_table;
  if (!args.material.empty()) {
    const auto material = ParseMaterialOption(args.material);
    if (!material.ok()) return ctx.UsageError(material.status().message());
    placement.material = *material;
  }

  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = client->AddObject(args.scene_id, args.id, placement);
  if (!response.ok()) return ctx.ServerError(response.status());
  return PrintPlaced(ctx, "added", response->object(), response->revision(), *response);
}

// The object's current pose, for moves that change only its rotation or only its position.
StatusOr<Pose3> CurrentPose(client::Client& client, const std::string& scene_id, const std::string& object_id) {
  ASSIGN_OR_RETURN(const v1::Scene scene, client.GetScene(scene_id));
  for (const auto& object : scene.objects()) {
    if (object.object_id() != object_id) continue;
    if (object.pose().kind_case() == v1::Pose::KIND_NOT_SET) return Pose3::Identity();
    return PoseFromProto(object.pose(), "object.pose");
  }
  return NotFound("object_id: no object '" + object_id + "' in scene '" + scene_id + "'");
}

int RunMove(Context& ctx, const ObjectArgs& args) {
  const auto parts = ParsePoseArgs(args.pose);
  if (!parts.ok()) return ctx.UsageError(parts.status().message());
  if (args.scale < 0 || !std::isfinite(args.scale)) return ctx.UsageError("--scale: must be a positive number");
  if (parts->empty() && args.scale == 0) return ctx.UsageError("nothing to change: give a pose option or --scale");

  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  std::optional<v1::Pose> pose;
  if (!parts->empty()) {
    Pose3 base = Pose3::Identity();
    if (!parts->complete()) {
      const auto current = CurrentPose(*client, args.scene_id, args.id);
      if (!current.ok()) return ctx.ServerError(current.status());
      base = *current;
    }
    pose = PoseToProto(ApplyPoseParts(*parts, base));
  }
  const auto response = client->MoveObject(args.scene_id, args.id, pose, args.scale);
  if (!response.ok()) return ctx.ServerError(response.status());
  return PrintPlaced(ctx, "moved", response->object(), response->revision(), *response);
}

int RunSetMaterial(Context& ctx, const ObjectArgs& args) {
  if (args.material.empty() == !args.clear_material) return ctx.UsageError("give --material or --clear, not both");
  std::optional<v1::Material> material;
  if (!args.clear_material) {
    const auto parsed = ParseMaterialOption(args.material);
    if (!parsed.ok()) return ctx.UsageError(parsed.status().message());
    material = *parsed;
  }
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = client->SetObjectMaterial(args.scene_id, args.id, material);
  if (!response.ok()) return ctx.ServerError(response.status());
  return PrintPlaced(ctx, "updated", response->object(), response->revision(), *response);
}

int RunRemove(Context& ctx, const ObjectArgs& args) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto revision = client->RemoveObject(args.scene_id, args.id);
  if (!revision.ok()) return ctx.ServerError(revision.status());
  if (ctx.json()) {
    v1::RemoveObjectResponse response;
    response.set_revision(*revision);
    ctx.EmitJson(ToJson(response));
  }
  ctx.Done("removed object " + args.id + "; scene revision " + std::to_string(*revision), "");
  return kExitOk;
}

}  // namespace

void AddObjectCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("object", "Place, move, set the material of and remove mesh instances in a scene");
  group->require_subcommand(1);

  auto add_args = std::make_shared<ObjectArgs>();
  auto* add = group->add_subcommand("add", "Add an instance of a mesh to a scene");
  add->add_option("SCENE", add_args->scene_id, "Scene id")->required();
  add->add_option("MESH", add_args->id, "Mesh id")->required();
  AddPoseOptions(add, add_args->pose);
  add->add_option("--scale", add_args->scale, "Uniform scale (default 1)");
  add->add_option("--label", add_args->label, "Free-form label");
  add->add_flag("--on-table", add_args->on_table, "Place the object on the rotary table (turns with it)");
  add->add_option("--material", add_args->material,
                  "Override the mesh's material: a preset (vscan materials) or "
                  "albedo=A,metallic=M,roughness=R,specular=S");
  OnRun(add, ctx, [&ctx, add_args] { return RunAdd(ctx, *add_args); });

  auto move_args = std::make_shared<ObjectArgs>();
  auto* move = group->add_subcommand("move", "Change an object's pose or scale (omitted parts are kept)");
  move->add_option("SCENE", move_args->scene_id, "Scene id")->required();
  move->add_option("OBJECT", move_args->id, "Object id")->required();
  AddPoseOptions(move, move_args->pose);
  move->add_option("--scale", move_args->scale, "New uniform scale");
  OnRun(move, ctx, [&ctx, move_args] { return RunMove(ctx, *move_args); });

  auto material_args = std::make_shared<ObjectArgs>();
  auto* set_material = group->add_subcommand("set-material", "Set or clear an object's material override");
  set_material->add_option("SCENE", material_args->scene_id, "Scene id")->required();
  set_material->add_option("OBJECT", material_args->id, "Object id")->required();
  set_material->add_option("--material", material_args->material,
                           "A preset (vscan materials) or albedo=A,metallic=M,roughness=R,specular=S");
  set_material->add_flag("--clear", material_args->clear_material, "Drop the override: the object takes its mesh's");
  OnRun(set_material, ctx, [&ctx, material_args] { return RunSetMaterial(ctx, *material_args); });

  auto remove_args = std::make_shared<ObjectArgs>();
  auto* remove = group->add_subcommand("remove", "Remove an object from a scene");
  remove->add_option("SCENE", remove_args->scene_id, "Scene id")->required();
  remove->add_option("OBJECT", remove_args->id, "Object id")->required();
  OnRun(remove, ctx, [&ctx, remove_args] { return RunRemove(ctx, *remove_args); });
}

}  // namespace vscan::cli
