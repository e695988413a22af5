#include "geometry/mesh_import.h"

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/ply_header.h"
#include "vscan/common/physical_limits.h"

namespace vscan::geometry {
namespace {

// Loaders for these formats build shallow trees; a deeper or larger one is not a mesh file.
constexpr size_t kMaxNodes = 1'000'000;
constexpr uint32_t kUnmapped = std::numeric_limits<uint32_t>::max();
constexpr size_t kMaxMessageBytes = 300;

// Parsing runs with validation only, which rejects out-of-range face indices (the PLY loader
// passes them through and later steps would read out of bounds); CheckParsedScene then guards
// the preconditions of the remaining steps before they run.
constexpr unsigned kParseFlags = aiProcess_ValidateDataStructure;
constexpr unsigned kPostProcessFlags =
    aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType | aiProcess_FindDegenerates;

// Refuses every file, so that only the bytes handed over are ever read (an OBJ's mtllib names
// a path of the uploader's choosing).
class NoFilesystem final : public Assimp::IOSystem {
 public:
  using IOSystem::Exists;
  using IOSystem::Open;
  bool Exists(const char*) const override { return false; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char*, const char*) override { return nullptr; }
  void Close(Assimp::IOStream* stream) override { delete stream; }
};

bool LooksLikeBinaryStl(std::string_view bytes) {
  if (bytes.size() < 84) return false;
  uint64_t count = 0;
  for (int i = 0; i < 4; ++i) count |= uint64_t{static_cast<unsigned char>(bytes[80 + i])} << (8 * i);
  return 84 + 50 * count == bytes.size();
}

const char* FormatHint(std::string_view bytes, MeshFileFormat format) {
  switch (format) {
    case MeshFileFormat::kPly:
      return "ply";
    case MeshFileFormat::kObj:
      return "obj";
    case MeshFileFormat::kStl:
      return "stl";
    case MeshFileFormat::kAuto:
      break;
  }
  // Binary STL first: many binary files open their 80-byte header with "solid" too.
  if (LooksLikeBinaryStl(bytes)) return "stl";
  if (bytes.starts_with("ply\n") || bytes.starts_with("ply\r\n")) return "ply";
  size_t start = bytes.find_first_not_of(" \t\r\n");
  if (start != std::string_view::npos && bytes.substr(start).starts_with("solid")) return "stl";
  return "obj";
}

// Faces without indices (a truncated PLY leaves one) trip an assertion in triangulation.
Status CheckParsedScene(const aiScene& scene) {
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* mesh = scene.mMeshes[m];
    if (mesh == nullptr || mesh->mNumFaces == 0) continue;
    if (mesh->mFaces == nullptr || mesh->mVertices == nullptr) return InvalidArgument("mesh data: malformed mesh");
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      if (mesh->mFaces[f].mNumIndices == 0 || mesh->mFaces[f].mIndices == nullptr) {
        return InvalidArgument("mesh data: face " + std::to_string(f) + " has no vertices");
      }
    }
  }
  return Status::Ok();
}

// assimp's message, without the placeholder name it gives in-memory files.
Status ParseError(const Assimp::Importer& importer) {
  std::string message = importer.GetErrorString();
  for (size_t at; (at = message.find(AI_MEMORYIO_MAGIC_FILENAME)) != std::string::npos;) {
    size_t end = message.find_first_of(" \"'", at);
    message.replace(at, (end == std::string::npos ? message.size() : end) - at, "the file");
  }
  if (message.size() > kMaxMessageBytes) message.resize(kMaxMessageBytes);
  return InvalidArgument("mesh data: " + (message.empty() ? std::string("cannot be parsed") : message));
}

struct MeshInstance {
  const aiMesh* mesh;
  Eigen::Matrix4d world_from_mesh;
};

Eigen::Matrix4d ToEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d out;
  for (unsigned r = 0; r < 4; ++r) {
    for (unsigned c = 0; c < 4; ++c) out(r, c) = m[r][c];
  }
  return out;
}

// Walks the node tree iteratively, composing each node's transformation with its parent's.
StatusOr<std::vector<MeshInstance>> CollectInstances(const aiScene& scene) {
  std::vector<MeshInstance> instances;
  if (scene.mRootNode == nullptr) return instances;
  std::vector<std::pair<const aiNode*, Eigen::Matrix4d>> pending;
  pending.emplace_back(scene.mRootNode, Eigen::Matrix4d::Identity());
  size_t visited = 0;
  while (!pending.empty()) {
    auto [node, parent] = std::move(pending.back());
    pending.pop_back();
    if (++visited > kMaxNodes) return InvalidArgument("mesh data: too many scene nodes");
    Eigen::Matrix4d world = parent * ToEigen(node->mTransformation);
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      unsigned index = node->mMeshes[i];
      if (index >= scene.mNumMeshes) return InvalidArgument("mesh data: node refers to a missing mesh");
      if (scene.mMeshes[index] != nullptr) instances.push_back({scene.mMeshes[index], world});
    }
    for (unsigned i = 0; i < node->mNumChildren; ++i) {
      if (node->mChildren[i] != nullptr) pending.emplace_back(node->mChildren[i], world);
    }
  }
  return instances;
}

struct VertexKey {
  uint32_t x, y, z;
  bool operator==(const VertexKey&) const = default;
};

struct VertexKeyHash {
  size_t operator()(const VertexKey& k) const {
    uint64_t h = (uint64_t{k.x} << 32 | k.y) * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) + uint64_t{k.z} * 0xBF58476D1CE4E5B9ull;
    return static_cast<size_t>(h ^ (h >> 32));
  }
};

// Accumulates triangles from all mesh instances, merging vertices with equal coordinates.
class MeshBuilder {
 public:
  explicit MeshBuilder(double metres_per_unit) : metres_per_unit_(metres_per_unit) {}

  Status Add(const MeshInstance& instance) {
    const aiMesh& mesh = *instance.mesh;
    if (mesh.mVertices == nullptr || mesh.mFaces == nullptr) return Status::Ok();
    std::vector<uint32_t> remap(mesh.mNumVertices, kUnmapped);
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;
      std::array<uint32_t, 3> triangle{};
      for (int k = 0; k < 3; ++k) {
        unsigned index = face.mIndices[k];
        if (index >= mesh.mNumVertices) return InvalidArgument("mesh data: face index out of range");
        if (remap[index] == kUnmapped) {
          ASSIGN_OR_RETURN(remap[index], Intern(mesh.mVertices[index], instance.world_from_mesh));
        }
        triangle[k] = remap[index];
      }
      // Vertices that only became equal after scaling leave a degenerate triangle behind.
      if (triangle[0] == triangle[1] || triangle[1] == triangle[2] || triangle[0] == triangle[2]) continue;
      mesh_.triangles.push_back(triangle);
    }
    return Status::Ok();
  }

  TriangleMesh Take() && { return std::move(mesh_); }

 private:
  StatusOr<uint32_t> Intern(const aiVector3D& v, const Eigen::Matrix4d& world_from_mesh) {
    Eigen::Vector4d local(v.x, v.y, v.z, 1.0);
    Eigen::Vector3d p = (world_from_mesh * local).head<3>() * metres_per_unit_;
    Eigen::Vector3f q;
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(p[i])) return InvalidArgument("mesh data: a vertex coordinate is not finite");
      if (std::abs(p[i]) > kMaxMeshCoordinateM) {
        return InvalidArgument("mesh data: a vertex lies beyond 10 km once scaled to metres (|x|, |y|, |z| <= 1e4 m)");
      }
      q[i] = static_cast<float>(p[i]) + 0.0f;  // + 0.0f turns -0 into +0 so they merge
    }
    VertexKey key{std::bit_cast<uint32_t>(q.x()), std::bit_cast<uint32_t>(q.y()), std::bit_cast<uint32_t>(q.z())};
    auto [it, inserted] = index_of_.try_emplace(key, static_cast<uint32_t>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(q);
    return it->second;
  }

  double metres_per_unit_;
  TriangleMesh mesh_;
  std::unordered_map<VertexKey, uint32_t, VertexKeyHash> index_of_;
};

}  // namespace

StatusOr<TriangleMesh> ImportMesh(std::string_view bytes, MeshFileFormat format, double metres_per_unit,
                                  uint64_t max_triangles) {
  if (!std::isfinite(metres_per_unit) || metres_per_unit <= 0) {
    return InvalidArgument("scale: metres per unit must be finite and positive, got " +
                           std::to_string(metres_per_unit));
  }
  if (bytes.empty()) return InvalidArgument("mesh data: empty");

  const char* hint = FormatHint(bytes, format);
  if (std::string_view(hint) == "ply") RETURN_IF_ERROR(CheckPlyHeader(bytes));

  // No DefaultLogger is ever created here, so assimp logs to its silent NullLogger.
  Assimp::Importer importer;
  importer.SetIOHandler(new NoFilesystem);  // the importer owns it
  importer.SetPropertyBool(AI_CONFIG_PP_FD_REMOVE, true);
  // The area test uses a fixed 1e-6 in file units and would drop real triangles of small meshes.
  importer.SetPropertyBool(AI_CONFIG_PP_FD_CHECKAREA, false);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), kParseFlags, hint);
  if (scene == nullptr) return ParseError(importer);
  RETURN_IF_ERROR(CheckParsedScene(*scene));
  scene = importer.ApplyPostProcessing(kPostProcessFlags);
  if (scene == nullptr) return ParseError(importer);

  ASSIGN_OR_RETURN(std::vector<MeshInstance> instances, CollectInstances(*scene));
  uint64_t triangle_count = 0;
  for (const auto& instance : instances) {
    const aiMesh& mesh = *instance.mesh;
    if (mesh.mFaces == nullptr) continue;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) triangle_count += mesh.mFaces[f].mNumIndices == 3;
  }
  if (triangle_count > max_triangles) {
    return ResourceExhausted("mesh data: " + std::to_string(triangle_count) + " triangles exceed the limit of " +
                             std::to_string(max_triangles));
  }

  MeshBuilder builder(metres_per_unit);
  for (const auto& instance : instances) RETURN_IF_ERROR(builder.Add(instance));
  TriangleMesh mesh = std::move(builder).Take();
  if (mesh.triangles.empty()) return InvalidArgument("mesh data: no triangles");
  return mesh;
}

}  // namespace vscan::geometry
