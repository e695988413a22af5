#include "campaign/campaign_setup.h"

#include <iostream>
#include <map>
#include <tuple>

#include "campaign/yaml_messages.h"
#include "robot/robot_format.h"
#include "session/describe.h"
#include "session/uploads.h"

namespace vscan::cli {
namespace {

// Objects that share a file, unit and scale share one uploaded mesh.
using MeshKey = std::tuple<std::string, int, double>;

int BuildScene(Context& ctx, const CampaignPlan& campaign, CampaignSetup* setup) {
  const PlanScene& plan = *campaign.scene;
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  std::map<MeshKey, std::string> meshes;
  for (const PlanObject& object : plan.objects) {
    const MeshKey key{object.mesh.string(), object.unit, object.scale};
    if (meshes.contains(key)) continue;
    client::MeshUploadOptions options;
    options.unit = object.unit;
    options.scale = object.scale;
    options.format = client::MeshFormatFromPath(object.mesh.string());
    v1::Mesh mesh;
    if (const int rc = UploadMesh(ctx, object.mesh.string(), options, &mesh); rc != kExitOk) return rc;
    setup->created_meshes.push_back(mesh.mesh_id());
    ctx.Say("uploaded mesh " + Describe(mesh));
    meshes[key] = mesh.mesh_id();
  }
  const auto scene = client->CreateScene(plan.name);
  if (!scene.ok()) return ReportCallError(ctx, campaign, PlanCall::kCreateScene, scene.status());
  setup->created_scene = setup->scene_id = scene->scene_id();
  ctx.Say("created scene " + scene->scene_id() + " '" + scene->name() + "'");
  for (size_t i = 0; i < plan.objects.size(); ++i) {
    const PlanObject& object = plan.objects[i];
    client::ObjectPlacement placement;
    if (object.pose) placement.pose = *object.pose;
    placement.label = object.label;
    placement.on_table = object.on_table;
    placement.material = object.material;
    const auto added =
        client->AddObject(scene->scene_id(), meshes.at({object.mesh.string(), object.unit, object.scale}), placement);
    if (!added.ok()) return ReportCallError(ctx, campaign, PlanCall::kAddObject, added.status(), i);
    ctx.Say("added object " + Describe(added->object()));
  }
  if (plan.table) {
    const auto table = client->SetRotaryTable(scene->scene_id(), *plan.table);
    if (!table.ok()) return ReportCallError(ctx, campaign, PlanCall::kSetRotaryTable, table.status());
    ctx.Say("table: " + Describe(table->table()));
  }
  return kExitOk;
}

int MountPlanRobot(Context& ctx, const CampaignPlan& campaign, CampaignSetup* setup) {
  const PlanRobot& plan = *campaign.robot;
  client::RobotUploadOptions options;
  options.urdf_path = plan.urdf;
  options.base_link = plan.base_link;
  options.tip_link = plan.tip_link;
  v1::Robot robot;
  if (const int rc = UploadRobot(ctx, plan.bundle.string(), options, "robot.urdf", &robot); rc != kExitOk) return rc;
  setup->created_robot = robot.robot_id();
  ctx.Say("uploaded robot " + Describe(robot) +
          (robot.warnings_size() > 0 ? " (`vscan robot get " + robot.robot_id() + "` lists them)" : ""));

  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  v1::MountRobotRequest request = plan.mount;
  request.set_scene_id(setup->scene_id);
  request.set_robot_id(robot.robot_id());
  const auto mounted = client->MountRobot(request);
  if (!mounted.ok()) return ReportCallError(ctx, campaign, PlanCall::kMountRobot, mounted.status());
  setup->created_mount = setup->mount_id = mounted->mount_id();
  ctx.Say("mounted " + Describe(mounted->mount()));
  return kExitOk;
}

// One deletion of UndoCampaignSetup: "what id" into *removed, or a warning.
void Remove(const std::string& what, const std::string& id, const Status& status, std::vector<std::string>* removed) {
  if (status.ok()) {
    removed->push_back(what + " " + id);
  } else {
    std::cerr << "warning: could not remove " << what << " " << id << ": " << status.message() << '\n';
  }
}

// Every preset the plan's objects name is one the server knows, before anything is uploaded.
int CheckMaterialPresets(Context& ctx, const CampaignPlan& plan) {
  if (!plan.scene) return kExitOk;
  std::vector<size_t> named;
  for (size_t i = 0; i < plan.scene->objects.size(); ++i) {
    const auto& material = plan.scene->objects[i].material;
    if (material && !material->preset().empty()) named.push_back(i);
  }
  if (named.empty()) return kExitOk;
  const auto presets = ctx.GetClient()->ListMaterialPresets();
  if (!presets.ok()) return ctx.ServerError(presets.status());
  std::string known;
  for (const v1::MaterialPreset& preset : *presets) known += (known.empty() ? "" : ", ") + preset.name();
  for (const size_t i : named) {
    const std::string& name = plan.scene->objects[i].material->preset();
    bool found = false;
    for (const v1::MaterialPreset& preset : *presets) found = found || preset.name() == name;
    if (found) continue;
    const std::string key = "scene.objects[" + std::to_string(i) + "].material";
    const auto mark = plan.key_marks.find(key);
    return ctx.UsageError(YamlReader(plan.source)
                              .Error(mark == plan.key_marks.end() ? YAML::Mark() : mark->second, key,
                                     "unknown preset '" + name + "' (" + known + ")")
                              .message());
  }
  return kExitOk;
}

}  // namespace

int ReportCallError(Context& ctx, const CampaignPlan& plan, PlanCall call, const Status& status, size_t object) {
  if (const auto located = LocateInPlan(plan, call, status, object)) return ctx.UsageError(*located);
  return ctx.ServerError(status);
}

int CheckPlanOnServer(Context& ctx, const CampaignPlan& plan) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  if (const int rc = CheckMaterialPresets(ctx, plan); rc != kExitOk) return rc;
  v1::CampaignSpec spec = plan.spec;
  spec.set_scene_id(plan.scene_id);
  spec.set_mount_id(plan.mount_id);
  const Status checked = client->ValidateCampaign(spec);
  return checked.ok() ? kExitOk : ReportCallError(ctx, plan, PlanCall::kStartCampaign, checked);
}

int SetUpCampaign(Context& ctx, const CampaignPlan& plan, CampaignSetup* setup) {
  setup->scene_id = plan.scene_id;
  setup->mount_id = plan.mount_id;
  if (plan.scene) {
    if (const int rc = BuildScene(ctx, plan, setup); rc != kExitOk) return rc;
  }
  if (plan.robot) {
    if (const int rc = MountPlanRobot(ctx, plan, setup); rc != kExitOk) return rc;
  }
  return kExitOk;
}

void UndoCampaignSetup(Context& ctx, const CampaignSetup& setup) {
  auto* client = ctx.GetClient();
  if (!client) return;
  // Reverse order: a mounted robot cannot be deleted, nor a mesh that objects use.
  std::vector<std::string> removed;
  if (!setup.created_mount.empty()) {
    Remove("mount", setup.created_mount, client->UnmountRobot(setup.created_mount).status(), &removed);
  }
  if (!setup.created_robot.empty()) {
    Remove("robot", setup.created_robot, client->DeleteRobot(setup.created_robot), &removed);
  }
  if (!setup.created_scene.empty()) {
    Remove("scene", setup.created_scene, client->DeleteScene(setup.created_scene), &removed);
  }
  for (const std::string& mesh : setup.created_meshes) Remove("mesh", mesh, client->DeleteMesh(mesh), &removed);
  if (removed.empty()) return;
  std::string list;
  for (const std::string& item : removed) list += (list.empty() ? "" : ", ") + item;
  std::cerr << "removed what this run had created: " << list << '\n';
}

}  // namespace vscan::cli
