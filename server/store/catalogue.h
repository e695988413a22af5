#pragma once
// The durable catalogue of meshes, scenes and objects: SQLite in WAL mode, synchronous=FULL.
// Every mutation is one transaction; scene mutations bump the scene's revision.
// Thread-safe: shares the Database's one connection and its lock.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "store/database.h"
#include "store/stored_enums.h"
#include "vscan/common/status.h"

struct sqlite3;

namespace vscan::store {

// A material as stored: a preset's name, or (preset empty) explicit values. The service checks it
// before it is stored; the catalogue keeps what it is given.
struct MaterialRecord {
  std::string preset;
  double albedo = 0.0;
  double metallic = 0.0;
  double roughness = 0.0;
  double specular_reflectance = 0.0;
  bool operator==(const MaterialRecord&) const = default;
};

struct MeshRecord {
  std::string mesh_id;
  std::string name;
  std::string sha256;  // blob holding the encoded mesh
  uint64_t vertex_count = 0;
  uint64_t triangle_count = 0;
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d bounds_max = Eigen::Vector3d::Zero();
  LengthUnit source_unit = LengthUnit::kUnspecified;
  double source_scale = 1.0;
  int64_t create_time_ms = 0;
  std::optional<MaterialRecord> material;  // the default of its objects; none: the engine's default
};

struct ObjectRecord {
  std::string object_id;
  std::string scene_id;
  std::string mesh_id;
  std::string label;
  Eigen::Matrix4d pose = Eigen::Matrix4d::Identity();  // parent_from_object
  double scale = 1.0;
  bool on_table = false;
  uint32_t instance_id = 0;
  std::optional<MaterialRecord> material;  // overrides the mesh's; none: the mesh's
};

struct TableRecord {
  bool enabled = false;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double angle_deg = 0.0;
};

struct SceneRecord {
  std::string scene_id;
  std::string name;
  uint64_t revision = 0;
  TableRecord table;
  std::vector<ObjectRecord> objects;  // ordered by instance_id
  int64_t create_time_ms = 0;
  int64_t update_time_ms = 0;
};

class Catalogue {
 public:
  explicit Catalogue(std::shared_ptr<Database> database);
  // Opens or creates the database file with its own Database (tests and tools).
  static StatusOr<std::unique_ptr<Catalogue>> Open(const std::filesystem::path& db_path);
  Database& database() { return *database_; }

  // Meshes. ids are generated ("msh_" + 16 hex digits).
  StatusOr<MeshRecord> InsertMesh(MeshRecord mesh);
  StatusOr<MeshRecord> GetMesh(const std::string& mesh_id);
  // Ordered by id; ids greater than after_id; at most limit (capped at 1000; INVALID_ARGUMENT when
  // not positive). The same holds for ListScenes.
  StatusOr<std::vector<MeshRecord>> ListMeshes(const std::string& after_id, int limit);
  // FAILED_PRECONDITION when objects still use it; returns its sha256 so the blob can go
  // when no other mesh shares it (second element: true when unshared).
  StatusOr<std::pair<std::string, bool>> DeleteMesh(const std::string& mesh_id);

  // Scenes. ids are generated ("scn_" + 16 hex digits); revision starts at 1.
  StatusOr<SceneRecord> CreateScene(const std::string& name);
  StatusOr<SceneRecord> GetScene(const std::string& scene_id);
  StatusOr<std::vector<SceneRecord>> ListScenes(const std::string& after_id, int limit);
  Status DeleteScene(const std::string& scene_id);

  // Objects. ids "obj_" + 16 hex; instance_id is the scene's next free number from 1.
  // NOT_FOUND for unknown scene or mesh (message names scene_id or mesh_id).
  StatusOr<std::pair<ObjectRecord, uint64_t>> AddObject(ObjectRecord object);
  // Adds every object to scene_id in one transaction and one new revision (each object's
  // scene_id is set). With new_mesh, that mesh is recorded in the same transaction (its id
  // generated) and the objects with an empty mesh_id use it. Returns the objects as stored,
  // the new mesh's id (empty without one) and the revision.
  struct AddedObjects {
    std::vector<ObjectRecord> objects;
    std::string new_mesh_id;
    uint64_t revision = 0;
  };
  StatusOr<AddedObjects> AddObjects(const std::string& scene_id, std::vector<ObjectRecord> objects,
                                    const MeshRecord* new_mesh = nullptr);
  // Replaces pose and, when scale is set, the scale. Returns the object and new revision.
  StatusOr<std::pair<ObjectRecord, uint64_t>> MoveObject(const std::string& scene_id, const std::string& object_id,
                                                         const Eigen::Matrix4d& pose, std::optional<double> scale);
  // Sets the object's material override (nullopt clears it). Returns the object and new revision.
  StatusOr<std::pair<ObjectRecord, uint64_t>> SetObjectMaterial(const std::string& scene_id,
                                                                const std::string& object_id,
                                                                const std::optional<MaterialRecord>& material);
  StatusOr<uint64_t> RemoveObject(const std::string& scene_id, const std::string& object_id);
  StatusOr<uint64_t> SetTable(const std::string& scene_id, const TableRecord& table);

 private:
  std::shared_ptr<Database> database_;
  std::mutex& mutex_;
  sqlite3* db_;
};

}  // namespace vscan::store
