#include "campaign_setup.h"

#include <map>
#include <tuple>

#include "describe.h"
#include "robot_format.h"
#include "uploads.h"

namespace vscan::cli {
namespace {

// Objects that share a file, unit and scale share one uploaded mesh.
using MeshKey = std::tuple<std::string, int, double>;

int BuildScene(Context& ctx, const PlanScene& plan, std::string* scene_id) {
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
    ctx.Say("uploaded mesh " + Describe(mesh));
    meshes[key] = mesh.mesh_id();
  }
  const auto scene = client->CreateScene(plan.name);
  if (!scene.ok()) return ctx.ServerError(scene.status());
  ctx.Say("created scene " + scene->scene_id() + " '" + scene->name() + "'");
  for (const PlanObject& object : plan.objects) {
    client::ObjectPlacement placement;
    if (object.pose) placement.pose = *object.pose;
    placement.label = object.label;
    placement.on_table = object.on_table;
    const auto added =
        client->AddObject(scene->scene_id(), meshes.at({object.mesh.string(), object.unit, object.scale}), placement);
    if (!added.ok()) return ctx.ServerError(added.status());
    ctx.Say("added object " + Describe(added->object()));
  }
  if (plan.table) {
    const auto table = client->SetRotaryTable(scene->scene_id(), *plan.table);
    if (!table.ok()) return ctx.ServerError(table.status());
    ctx.Say("table: " + Describe(table->table()));
  }
  *scene_id = scene->scene_id();
  return kExitOk;
}

int MountPlanRobot(Context& ctx, const PlanRobot& plan, const std::string& scene_id, std::string* mount_id) {
  client::RobotUploadOptions options;
  options.urdf_path = plan.urdf;
  options.base_link = plan.base_link;
  options.tip_link = plan.tip_link;
  v1::Robot robot;
  if (const int rc = UploadRobot(ctx, plan.bundle.string(), options, "robot.urdf", &robot); rc != kExitOk) return rc;
  ctx.Say("uploaded robot " + Describe(robot) +
          (robot.warnings_size() > 0 ? " (`vscan robot get " + robot.robot_id() + "` lists them)" : ""));

  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  v1::MountRobotRequest request = plan.mount;
  request.set_scene_id(scene_id);
  request.set_robot_id(robot.robot_id());
  const auto mounted = client->MountRobot(request);
  if (!mounted.ok()) return ctx.ServerError(mounted.status());
  ctx.Say("mounted " + Describe(mounted->mount()));
  *mount_id = mounted->mount_id();
  return kExitOk;
}

}  // namespace

int SetUpCampaign(Context& ctx, const CampaignPlan& plan, CampaignSetup* setup) {
  setup->scene_id = plan.scene_id;
  setup->mount_id = plan.mount_id;
  if (plan.scene) {
    if (const int rc = BuildScene(ctx, *plan.scene, &setup->scene_id); rc != kExitOk) return rc;
  }
  if (plan.robot) {
    if (const int rc = MountPlanRobot(ctx, *plan.robot, setup->scene_id, &setup->mount_id); rc != kExitOk) return rc;
  }
  return kExitOk;
}

}  // namespace vscan::cli
