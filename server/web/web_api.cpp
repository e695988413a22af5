#include "web/web_api.h"

#include <cctype>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "scenes/object_material.h"
#include "scenes/scene_registry.h"
#include "web/web_encode.h"

namespace vscan::web {
namespace {

constexpr const char* kJson = "application/json";
constexpr const char* kText = "text/plain; charset=utf-8";

WebReply Text(int status, std::string message) { return {status, kText, std::move(message) + "\n"}; }

// Compares every byte whatever the first difference, so that timing does not reveal the token.
bool SameToken(std::string_view sent, std::string_view token) {
  if (sent.size() != token.size()) return false;
  unsigned char difference = 0;
  for (size_t i = 0; i < token.size(); ++i) difference |= static_cast<unsigned char>(sent[i] ^ token[i]);
  return difference == 0;
}

bool Authorized(std::string_view authorization, const std::string& token) {
  if (token.empty()) return true;
  constexpr std::string_view kBearer = "Bearer ";
  if (authorization.size() < kBearer.size()) return false;
  for (size_t i = 0; i < kBearer.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(authorization[i])) !=
        std::tolower(static_cast<unsigned char>(kBearer[i]))) {
      return false;
    }
  }
  return SameToken(authorization.substr(kBearer.size()), token);
}

// Catalogue errors as HTTP statuses; only NOT_FOUND is the client's to see in detail.
WebReply FromStatus(const Status& status) {
  if (status.code() == StatusCode::kNotFound) return Text(404, status.ToString());
  if (status.code() == StatusCode::kInvalidArgument) return Text(400, status.ToString());
  spdlog::warn("web view: {}", status.ToString());
  return Text(500, "internal error");
}

// An id is one path segment of letters, digits, '_' and '-' (the catalogue's ids are "scn_..." etc.).
bool IsId(std::string_view id) {
  if (id.empty() || id.size() > 128) return false;
  for (const char c : id) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  }
  return true;
}

}  // namespace

WebApi::WebApi(scenes::SceneRegistry& registry, WebApiOptions options)
    : registry_(registry), options_(std::move(options)) {}

WebReply WebApi::Handle(std::string_view method, std::string_view path, std::string_view authorization) const {
  if (method != "GET") return Text(405, "the web view is read-only: only GET is served");
  if (!Authorized(authorization, options_.token)) return Text(401, "authorization: missing or wrong bearer token");
  constexpr std::string_view kScenes = "/api/scenes";
  constexpr std::string_view kMeshes = "/api/meshes/";
  if (path == kScenes || path == "/api/scenes/") return Scenes();
  if (path.starts_with("/api/scenes/")) {
    const std::string_view id = path.substr(kScenes.size() + 1);
    if (!IsId(id)) return Text(404, fmt::format("no scene '{}'", id));
    return Scene(std::string(id));
  }
  if (path.starts_with(kMeshes)) {
    const std::string_view id = path.substr(kMeshes.size());
    if (!IsId(id)) return Text(404, fmt::format("no mesh '{}'", id));
    return Mesh(std::string(id));
  }
  return Text(404, fmt::format("no such resource: {}", path));
}

WebReply WebApi::Scenes() const {
  auto scenes = registry_.catalogue().ListScenes("", options_.max_scenes);
  if (!scenes.ok()) return FromStatus(scenes.status());
  return {200, kJson, ScenesJson(*scenes)};
}

WebReply WebApi::Scene(const std::string& scene_id) const {
  auto scene = registry_.catalogue().GetScene(scene_id);
  if (!scene.ok()) return FromStatus(scene.status());
  std::vector<PlacedObject> placed;
  placed.reserve(scene->objects.size());
  for (const store::ObjectRecord& object : scene->objects) {
    auto mesh = registry_.catalogue().GetMesh(object.mesh_id);
    if (!mesh.ok()) return FromStatus(mesh.status());
    auto material = scenes::EffectiveMaterial(object, *mesh);
    if (!material.ok()) return FromStatus(material.status());
    const std::optional<store::MaterialRecord>& chosen = object.material ? object.material : mesh->material;
    placed.push_back({object, scenes::SceneRegistry::WorldFromObject(*scene, object, scene->table.angle_deg).matrix(),
                      chosen ? chosen->preset : sensor::MaterialPresets().front().name, *material});
  }
  return {200, kJson, SceneJson(*scene, placed)};
}

WebReply WebApi::Mesh(const std::string& mesh_id) const {
  auto record = registry_.catalogue().GetMesh(mesh_id);
  if (!record.ok()) return FromStatus(record.status());
  if (record->triangle_count > options_.max_mesh_triangles) {
    return Text(422, fmt::format("mesh {} has {} triangles; the web view sends at most {}", mesh_id,
                                 record->triangle_count, options_.max_mesh_triangles));
  }
  auto mesh = registry_.LoadMesh(mesh_id);
  if (!mesh.ok()) return FromStatus(mesh.status());
  return {200, "application/octet-stream", MeshBinary(**mesh)};
}

}  // namespace vscan::web
