#include <map>

#include "session/commands.h"
#include "session/describe.h"

namespace vscan::cli {
namespace {

void AddCreate(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("create", "Create an empty scene");
  auto name = std::make_shared<std::string>();
  cmd->add_option("NAME", *name, "Scene name")->required();
  OnRun(cmd, ctx, [&ctx, name]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto scene = client->CreateScene(*name);
    if (!scene.ok()) return ctx.ServerError(scene.status());
    if (ctx.json()) ctx.EmitJson(ToJson(*scene));
    ctx.Done("created scene " + scene->scene_id() + " '" + scene->name() + "'", scene->scene_id());
    return kExitOk;
  });
}

void AddSceneList(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("list", "List scenes");
  OnRun(cmd, ctx, [&ctx]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto scenes = client->ListScenes();
    if (!scenes.ok()) return ctx.ServerError(scenes.status());
    if (ctx.json()) {
      v1::ListScenesResponse all;
      for (const auto& s : *scenes) *all.add_scenes() = s;
      ctx.EmitJson(ToJson(all));
      return kExitOk;
    }
    for (const auto& s : *scenes) {
      ctx.Print(ctx.quiet() ? s.scene_id()
                            : s.scene_id() + "  '" + s.name() + "'  revision " + std::to_string(s.revision()) +
                                  "  " + std::to_string(s.objects_size()) + " objects");
    }
    return kExitOk;
  });
}

void AddSceneGet(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("get", "Show a scene: objects and rotary table");
  auto id = std::make_shared<std::string>();
  cmd->add_option("ID", *id, "Scene id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto scene = client->GetScene(*id);
    if (!scene.ok()) return ctx.ServerError(scene.status());
    if (ctx.json()) {
      ctx.EmitJson(ToJson(*scene));
      return kExitOk;
    }
    ctx.Print("scene " + scene->scene_id() + " '" + scene->name() + "' revision " + std::to_string(scene->revision()));
    ctx.Print("table: " + Describe(scene->table()));
    std::map<std::string, std::string> mesh_materials;  // by mesh id, for objects with no override
    for (const auto& object : scene->objects()) {
      std::string line = "object " + Describe(object);
      if (!object.has_material()) {
        auto known = mesh_materials.find(object.mesh_id());
        if (known == mesh_materials.end()) {
          const auto mesh = client->GetMesh(object.mesh_id());
          const std::string from = !mesh.ok()            ? "?"
                                   : mesh->has_material() ? Describe(mesh->material()) + " (the mesh's)"
                                                          : "matte-grey (default)";
          known = mesh_materials.emplace(object.mesh_id(), from).first;
        }
        line += "  material " + known->second;
      }
      ctx.Print(line);
    }
    return kExitOk;
  });
}

void AddSceneDelete(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("delete", "Delete a scene");
  auto id = std::make_shared<std::string>();
  cmd->add_option("ID", *id, "Scene id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const Status status = client->DeleteScene(*id);
    if (!status.ok()) return ctx.ServerError(status);
    if (ctx.json()) ctx.EmitJson("{\"sceneId\":" + JsonQuote(*id) + ",\"deleted\":true}");
    ctx.Done("deleted scene " + *id, "");
    return kExitOk;
  });
}

}  // namespace

void AddSceneCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("scene", "Create, list, show and delete scenes");
  group->require_subcommand(1);
  AddCreate(*group, ctx);
  AddSceneList(*group, ctx);
  AddSceneGet(*group, ctx);
  AddSceneDelete(*group, ctx);
}

}  // namespace vscan::cli
