#include "bins/bin_setup.h"

#include <iostream>
#include <map>
#include <utility>

#include "session/describe.h"
#include "session/uploads.h"

namespace vscan::cli {
namespace {

// The mesh's id: given, uploaded before by this run, or uploaded now.
int MeshIdOf(Context& ctx, const BinPlanPart& source, std::map<std::pair<std::string, int>, std::string>& uploaded,
             BinSetup* setup, std::string* mesh_id) {
  *mesh_id = source.mesh_id;
  if (!mesh_id->empty()) return kExitOk;
  const auto key = std::make_pair(source.mesh.string(), static_cast<int>(source.unit));
  if (const auto found = uploaded.find(key); found != uploaded.end()) {
    *mesh_id = found->second;
    return kExitOk;
  }
  client::MeshUploadOptions options;
  options.unit = source.unit;
  options.format = client::MeshFormatFromPath(source.mesh.string());
  v1::Mesh mesh;
  if (const int rc = UploadMesh(ctx, source.mesh.string(), options, &mesh); rc != kExitOk) return rc;
  setup->created_meshes.push_back(mesh.mesh_id());
  ctx.Say("uploaded mesh " + Describe(mesh));
  uploaded[key] = *mesh_id = mesh.mesh_id();
  return kExitOk;
}

}  // namespace

int ReportBinError(Context& ctx, const BinPlan& plan, const Status& status) {
  if (const auto located = LocateInBinPlan(plan, status)) return ctx.UsageError(*located);
  return ctx.ServerError(status);
}

int CheckBinPlanOnServer(Context& ctx, const BinPlan& plan) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  v1::BinFillSpec spec = plan.spec;
  spec.set_scene_id(plan.scene_id);
  for (size_t i = 0; i < plan.parts.size(); ++i) spec.mutable_parts(static_cast<int>(i))->set_mesh_id(plan.parts[i].mesh_id);
  if (plan.bin_mesh) spec.mutable_bin_mesh()->set_mesh_id(plan.bin_mesh->mesh_id);
  const Status checked = client->ValidateBinFill(spec);
  return checked.ok() ? kExitOk : ReportBinError(ctx, plan, checked);
}

int SetUpBin(Context& ctx, const BinPlan& plan, BinSetup* setup) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  setup->spec = plan.spec;
  setup->scene_id = plan.scene_id;
  if (setup->scene_id.empty()) {
    const auto scenes = client->ListScenes();
    if (!scenes.ok()) return ctx.ServerError(scenes.status());
    for (const v1::Scene& scene : *scenes) {
      if (scene.name() == plan.scene_name) setup->scene_id = scene.scene_id();
    }
    if (setup->scene_id.empty()) {
      const auto scene = client->CreateScene(plan.scene_name);
      if (!scene.ok()) return ctx.ServerError(scene.status());
      setup->created_scene = setup->scene_id = scene->scene_id();
      ctx.Say("created scene " + scene->scene_id() + " '" + scene->name() + "'");
    } else {
      ctx.Say("using scene " + setup->scene_id + " '" + plan.scene_name + "'");
    }
  }
  setup->spec.set_scene_id(setup->scene_id);
  // Meshes that share a file and unit share one upload.
  std::map<std::pair<std::string, int>, std::string> uploaded;
  for (size_t i = 0; i < plan.parts.size(); ++i) {
    std::string mesh_id;
    if (const int rc = MeshIdOf(ctx, plan.parts[i], uploaded, setup, &mesh_id); rc != kExitOk) return rc;
    setup->spec.mutable_parts(static_cast<int>(i))->set_mesh_id(mesh_id);
  }
  if (plan.bin_mesh) {
    std::string mesh_id;
    if (const int rc = MeshIdOf(ctx, *plan.bin_mesh, uploaded, setup, &mesh_id); rc != kExitOk) return rc;
    setup->spec.mutable_bin_mesh()->set_mesh_id(mesh_id);
  }
  return kExitOk;
}

void UndoBinSetup(Context& ctx, const BinSetup& setup) {
  auto* client = ctx.GetClient();
  if (!client) return;
  std::string removed;
  const auto remove = [&removed](const std::string& what, const std::string& id, const Status& status) {
    if (status.ok()) {
      removed += (removed.empty() ? "" : ", ") + what + " " + id;
    } else {
      std::cerr << "warning: could not remove " << what << " " << id << ": " << status.message() << '\n';
    }
  };
  if (!setup.created_scene.empty()) remove("scene", setup.created_scene, client->DeleteScene(setup.created_scene));
  for (const std::string& mesh : setup.created_meshes) remove("mesh", mesh, client->DeleteMesh(mesh));
  if (!removed.empty()) std::cerr << "removed what this run had created: " << removed << '\n';
}

}  // namespace vscan::cli
