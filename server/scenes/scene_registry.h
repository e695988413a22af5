#pragma once
// Scenes as the scanner sees them: catalogue records turned into cached Embree scenes.
// One Embree scene is built per (scene, revision, table angle) and shared by concurrent scans.

#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "geometry/mesh_import.h"
#include "geometry/sandboxed_import.h"
#include "raycast/raycast_scene.h"
#include "store/blob_store.h"
#include "store/catalogue.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"

namespace vscan::scenes {

// What a scan needs: the scene as it was read and its ray-casting structure.
struct ScanTarget {
  store::SceneRecord scene;
  std::shared_ptr<const raycast::RaycastScene> raycast;
  // The placed meshes the raycast scene was built from (what the raster backends draw).
  std::shared_ptr<const std::vector<raycast::SceneInstance>> instances;
  // Names this (scene, revision, table angle) for caches outside the registry.
  std::string cache_key;
};

// Parameters of an uploaded mesh file.
struct MeshUpload {
  std::string name;
  geometry::MeshFileFormat format = geometry::MeshFileFormat::kAuto;
  store::LengthUnit unit = store::LengthUnit::kUnspecified;  // recorded for the user
  double metres_per_unit = 1.0;
  double scale = 1.0;
  std::optional<store::MaterialRecord> material;  // the mesh's default material; checked by the caller
};

class SceneRegistry {
 public:
  // With import_sandbox, uploads are parsed by its helper process; without, in this process.
  SceneRegistry(store::Catalogue& catalogue, store::BlobStore& blobs, size_t cache_entries = 8,
                std::optional<geometry::ImportSandbox> import_sandbox = std::nullopt);

  store::Catalogue& catalogue() { return catalogue_; }

  // Parses, normalises to metres, stores the geometry blob durably, then records the mesh.
  StatusOr<store::MeshRecord> AddMesh(std::string_view file_bytes, const MeshUpload& upload);
  Status DeleteMesh(const std::string& mesh_id);
  // Stores a mesh the server built (metres) and records it with objects in scene_id, in one
  // transaction and one revision; objects with an empty mesh_id use the new mesh.
  StatusOr<store::Catalogue::AddedObjects> AddObjectsWithMesh(const std::string& scene_id, const TriangleMesh& mesh,
                                                              const std::string& mesh_name,
                                                              std::vector<store::ObjectRecord> objects);
  StatusOr<std::shared_ptr<const TriangleMesh>> LoadMesh(const std::string& mesh_id);

  // Reads the scene and returns its Embree scene, built or from the cache.
  StatusOr<ScanTarget> PrepareScan(const std::string& scene_id, std::optional<double> table_angle_deg);

  // Parses a mesh file of user data the way uploads are parsed (in the sandbox when there is one).
  StatusOr<TriangleMesh> ImportUserMesh(std::string_view file_bytes, geometry::MeshFileFormat format,
                                        double metres_per_unit = 1.0);

  // base with extra instances added (e.g. robot links at given joint positions). The result is
  // cached under base.cache_key + "|" + extra_key, which names it for outside caches too; the
  // same key must always come with the same extras.
  StatusOr<ScanTarget> WithExtraInstances(const ScanTarget& base, const std::string& extra_key,
                                          std::vector<raycast::SceneInstance> extra);

  // world_from_object of an object, including the table's turn for objects on the table.
  static Pose3 WorldFromObject(const store::SceneRecord& scene, const store::ObjectRecord& object,
                               double table_angle_deg);

 private:
  using CacheKey = std::tuple<std::string, uint64_t, double>;
  struct Built {
    std::shared_ptr<const raycast::RaycastScene> raycast;
    std::shared_ptr<const std::vector<raycast::SceneInstance>> instances;
  };
  StatusOr<Built> Build(const store::SceneRecord& scene, double table_angle);
  // The decoded geometry of a mesh row, from the cache or its blob.
  StatusOr<std::shared_ptr<const TriangleMesh>> LoadGeometry(const store::MeshRecord& record);

  store::Catalogue& catalogue_;
  store::BlobStore& blobs_;
  size_t cache_entries_;
  std::optional<geometry::ImportSandbox> import_sandbox_;

  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const TriangleMesh>> meshes_;  // by sha256
  std::list<std::pair<CacheKey, Built>> scenes_;  // most recent first
  std::list<std::pair<std::string, Built>> extended_;  // WithExtraInstances, most recent first
};

}  // namespace vscan::scenes
