#include "scenes/scene_registry.h"

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "scenes/object_material.h"
#include "store/blob_gc.h"

namespace vscan::scenes {
namespace {

constexpr size_t kMeshCacheEntries = 64;

double DegToRad(double deg) { return deg * std::numbers::pi / 180.0; }

// The catalogue row of a mesh stored as blob sha256: its counts and bounds (source unit left to the caller).
store::MeshRecord MeshRecordOf(const TriangleMesh& mesh, const std::string& name, const std::string& sha256) {
  store::MeshRecord record;
  record.name = name;
  record.sha256 = sha256;
  record.vertex_count = mesh.vertices.size();
  record.triangle_count = mesh.triangles.size();
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  record.bounds_min = lo.cast<double>();
  record.bounds_max = hi.cast<double>();
  return record;
}

}  // namespace

SceneRegistry::SceneRegistry(store::Catalogue& catalogue, store::BlobStore& blobs, size_t cache_entries,
                             std::optional<geometry::ImportSandbox> import_sandbox)
    : catalogue_(catalogue),
      blobs_(blobs),
      cache_entries_(cache_entries),
      import_sandbox_(std::move(import_sandbox)) {}

StatusOr<store::MeshRecord> SceneRegistry::AddMesh(std::string_view file_bytes, const MeshUpload& upload) {
  if (!std::isfinite(upload.scale) || upload.scale <= 0) return InvalidArgument("header.scale: must be positive");
  const double metres_per_unit = upload.metres_per_unit * upload.scale;
  ASSIGN_OR_RETURN(TriangleMesh mesh,
                   import_sandbox_
                       ? geometry::ImportMeshIsolated(file_bytes, upload.format, metres_per_unit, *import_sandbox_)
                       : geometry::ImportMesh(file_bytes, upload.format, metres_per_unit));
  const std::string encoded = geometry::EncodeMesh(mesh);
  // A full disk or a failing store names the mesh it was storing.
  auto storing = [&](const Status& status) {
    return Status(status.code(), "storing mesh '" + upload.name + "': " + status.message());
  };
  // Pinned until its row is stored, so that a concurrent delete cannot collect it meanwhile.
  auto pin = blobs_.PutPinned(encoded);
  if (!pin.ok()) return storing(pin.status());
  const std::string& sha = pin->sha256();

  store::MeshRecord record = MeshRecordOf(mesh, upload.name, sha);
  record.source_unit = upload.unit;
  record.source_scale = upload.scale;
  record.material = upload.material;
  auto inserted = catalogue_.InsertMesh(record);
  if (!inserted.ok()) return storing(inserted.status());
  store::MeshRecord stored = std::move(inserted).value();
  spdlog::info("mesh {} '{}' stored: {} triangles, blob {}", stored.mesh_id, stored.name, stored.triangle_count,
               sha.substr(0, 12));
  return stored;
}

StatusOr<store::Catalogue::AddedObjects> SceneRegistry::AddObjectsWithMesh(const std::string& scene_id,
                                                                           const TriangleMesh& mesh,
                                                                           const std::string& mesh_name,
                                                                           std::vector<store::ObjectRecord> objects) {
  // Pinned until the rows naming it are stored.
  ASSIGN_OR_RETURN(const store::BlobPin pin, blobs_.PutPinned(geometry::EncodeMesh(mesh)));
  store::MeshRecord record = MeshRecordOf(mesh, mesh_name, pin.sha256());
  record.source_unit = store::LengthUnit::kMetre;
  return catalogue_.AddObjects(scene_id, std::move(objects), &record);
}

Status SceneRegistry::DeleteMesh(const std::string& mesh_id) {
  ASSIGN_OR_RETURN(auto deleted, catalogue_.DeleteMesh(mesh_id));
  const auto& [sha, unshared] = deleted;
  if (unshared) {
    std::lock_guard lock(mutex_);
    meshes_.erase(sha);
  }
  // The blob goes when no row of any table names it; a failure here only leaves an orphan file.
  const auto collected = store::CollectBlobs(catalogue_.database(), blobs_, {sha});
  if (!collected.ok()) spdlog::warn("mesh {}: blob not removed: {}", mesh_id, collected.status().ToString());
  return Status::Ok();
}

StatusOr<std::shared_ptr<const TriangleMesh>> SceneRegistry::LoadMesh(const std::string& mesh_id) {
  ASSIGN_OR_RETURN(store::MeshRecord record, catalogue_.GetMesh(mesh_id));
  return LoadGeometry(record);
}

StatusOr<std::shared_ptr<const TriangleMesh>> SceneRegistry::LoadGeometry(const store::MeshRecord& record) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = meshes_.find(record.sha256); it != meshes_.end()) return it->second;
  }
  ASSIGN_OR_RETURN(std::string bytes, blobs_.Get(record.sha256));
  ASSIGN_OR_RETURN(TriangleMesh mesh, geometry::DecodeMesh(bytes));
  auto shared = std::make_shared<const TriangleMesh>(std::move(mesh));
  std::lock_guard lock(mutex_);
  if (meshes_.size() >= kMeshCacheEntries) meshes_.erase(meshes_.begin());
  meshes_.emplace(record.sha256, shared);
  return shared;
}

StatusOr<TriangleMesh> SceneRegistry::ImportUserMesh(std::string_view file_bytes, geometry::MeshFileFormat format,
                                                     double metres_per_unit) {
  return import_sandbox_ ? geometry::ImportMeshIsolated(file_bytes, format, metres_per_unit, *import_sandbox_)
                         : geometry::ImportMesh(file_bytes, format, metres_per_unit);
}

StatusOr<ScanTarget> SceneRegistry::WithExtraInstances(const ScanTarget& base, const std::string& extra_key,
                                                       std::vector<raycast::SceneInstance> extra) {
  const std::string key = base.cache_key + "|" + extra_key;
  {
    std::lock_guard lock(mutex_);
    for (auto it = extended_.begin(); it != extended_.end(); ++it) {
      if (it->first == key) {
        extended_.splice(extended_.begin(), extended_, it);
        const Built& hit = extended_.front().second;
        return ScanTarget{base.scene, hit.raycast, hit.instances, key};
      }
    }
  }
  auto instances = std::make_shared<std::vector<raycast::SceneInstance>>(*base.instances);
  instances->insert(instances->end(), std::make_move_iterator(extra.begin()), std::make_move_iterator(extra.end()));
  ASSIGN_OR_RETURN(auto raycast, raycast::RaycastScene::Build(*instances));
  Built built{std::move(raycast), std::move(instances)};
  std::lock_guard lock(mutex_);
  extended_.emplace_front(key, built);
  while (extended_.size() > cache_entries_) extended_.pop_back();
  return ScanTarget{base.scene, built.raycast, built.instances, key};
}

Pose3 SceneRegistry::WorldFromObject(const store::SceneRecord& scene, const store::ObjectRecord& object,
                                     double table_angle_deg) {
  Pose3 pose(object.pose);
  if (object.on_table && scene.table.enabled) {
    pose = RotationAboutLine(scene.table.centre, scene.table.axis, DegToRad(table_angle_deg)) * pose;
  }
  return pose;
}

StatusOr<ScanTarget> SceneRegistry::PrepareScan(const std::string& scene_id, std::optional<double> table_angle_deg) {
  ASSIGN_OR_RETURN(store::SceneRecord scene, catalogue_.GetScene(scene_id));
  const double angle = table_angle_deg.value_or(scene.table.angle_deg);
  const CacheKey key{scene.scene_id, scene.revision, scene.table.enabled ? angle : 0.0};
  const std::string cache_key = scene.scene_id + "@" + std::to_string(scene.revision) + "@" +
                                std::to_string(std::get<2>(key));
  {
    std::lock_guard lock(mutex_);
    for (auto it = scenes_.begin(); it != scenes_.end(); ++it) {
      if (it->first == key) {
        scenes_.splice(scenes_.begin(), scenes_, it);
        const Built& hit = scenes_.front().second;
        return ScanTarget{std::move(scene), hit.raycast, hit.instances, cache_key};
      }
    }
  }
  ASSIGN_OR_RETURN(Built built, Build(scene, angle));
  std::lock_guard lock(mutex_);
  scenes_.emplace_front(key, built);
  while (scenes_.size() > cache_entries_) scenes_.pop_back();
  return ScanTarget{std::move(scene), built.raycast, built.instances, cache_key};
}

StatusOr<SceneRegistry::Built> SceneRegistry::Build(const store::SceneRecord& scene, double table_angle) {
  auto instances = std::make_shared<std::vector<raycast::SceneInstance>>();
  instances->reserve(scene.objects.size());
  for (const auto& object : scene.objects) {
    ASSIGN_OR_RETURN(const store::MeshRecord record, catalogue_.GetMesh(object.mesh_id));
    ASSIGN_OR_RETURN(auto mesh, LoadGeometry(record));
    ASSIGN_OR_RETURN(const sensor::Material material, EffectiveMaterial(object, record));
    instances->push_back(
        {mesh, WorldFromObject(scene, object, table_angle), object.scale, object.instance_id, material});
  }
  ASSIGN_OR_RETURN(auto raycast, raycast::RaycastScene::Build(*instances));
  spdlog::debug("scene {} revision {}: built ray-casting structure over {} triangles", scene.scene_id,
                scene.revision, raycast->triangle_count());
  return Built{std::move(raycast), std::move(instances)};
}

}  // namespace vscan::scenes
