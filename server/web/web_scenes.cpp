#include "web/web_scenes.h"

#include <optional>
#include <vector>

#include <fmt/format.h>

#include "scenes/object_material.h"
#include "scenes/scene_registry.h"
#include "service/robot/robot_links.h"
#include "web/web_api.h"
#include "web/web_encode.h"

namespace vscan::web {
namespace {

WebReply Scenes(scenes::SceneRegistry& registry, const WebApiOptions& options) {
  auto scenes = registry.catalogue().ListScenes("", options.max_scenes);
  if (!scenes.ok()) return FromStatus(scenes.status());
  return JsonReply(ScenesJson(*scenes));
}

WebReply Scene(scenes::SceneRegistry& registry, robot_registry::RobotRegistry* robots, const std::string& scene_id) {
  auto scene = registry.catalogue().GetScene(scene_id);
  if (!scene.ok()) return FromStatus(scene.status());
  std::vector<PlacedObject> placed;
  placed.reserve(scene->objects.size());
  for (const store::ObjectRecord& object : scene->objects) {
    auto mesh = registry.catalogue().GetMesh(object.mesh_id);
    if (!mesh.ok()) return FromStatus(mesh.status());
    auto material = scenes::EffectiveMaterial(object, *mesh);
    if (!material.ok()) return FromStatus(material.status());
    const std::optional<store::MaterialRecord>& chosen = object.material ? object.material : mesh->material;
    placed.push_back({object, scenes::SceneRegistry::WorldFromObject(*scene, object, scene->table.angle_deg).matrix(),
                      chosen ? chosen->preset : sensor::MaterialPresets().front().name, *material});
  }
  std::vector<store::MountRecord> mounts;
  if (robots) {
    auto listed = service::SceneMounts(*robots, scene_id);
    if (!listed.ok()) return FromStatus(listed.status());
    mounts = std::move(listed).value();
  }
  return JsonReply(SceneJson(*scene, placed, mounts));
}

WebReply Mesh(scenes::SceneRegistry& registry, const WebApiOptions& options, const std::string& mesh_id) {
  auto record = registry.catalogue().GetMesh(mesh_id);
  if (!record.ok()) return FromStatus(record.status());
  if (record->triangle_count > options.max_mesh_triangles) {
    return TextReply(422, fmt::format("mesh {} has {} triangles; the web view sends at most {}", mesh_id,
                                      record->triangle_count, options.max_mesh_triangles));
  }
  auto mesh = registry.LoadMesh(mesh_id);
  if (!mesh.ok()) return FromStatus(mesh.status());
  return {200, kBinaryType, MeshBinary(**mesh), {}};
}

}  // namespace

WebReply ServeScenes(const WebSources& sources, const WebApiOptions& options, const WebRequest& request) {
  if (!sources.scenes) return TextReply(404, "scenes are not served");
  const auto& segments = request.segments;
  const bool scenes = segments[0] == "scenes";
  if (scenes && (segments.size() == 1 || (segments.size() == 2 && segments[1].empty()))) {
    return Scenes(*sources.scenes, options);
  }
  if (segments.size() != 2 || !IsId(segments[1])) {
    return TextReply(404, fmt::format("no {} '{}'", scenes ? "scene" : "mesh", segments.size() > 1 ? segments[1] : ""));
  }
  const std::string id(segments[1]);
  return scenes ? Scene(*sources.scenes, sources.robots, id) : Mesh(*sources.scenes, options, id);
}

}  // namespace vscan::web
