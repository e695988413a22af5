#include "service/datasets/format/models_info.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "service/job/json_writer.h"
#include "service/datasets/format/bop_units.h"

namespace vscan::service::dataset {
namespace {

void WriteSymmetries(JsonWriter& json, const PartModel& part) {
  if (!part.discrete_symmetries.empty()) {
    json.Key("symmetries_discrete").Open('[');
    for (const Pose3& symmetry : part.discrete_symmetries) {
      Pose3 in_mm = symmetry;
      in_mm.translation() *= kMillimetresPerMetre;
      json.Matrix(in_mm);
    }
    json.Close(']');
  }
  if (!part.continuous_symmetries.empty()) {
    json.Key("symmetries_continuous").Open('[');
    for (const PartModel::ContinuousSymmetry& symmetry : part.continuous_symmetries) {
      json.Open('{').Key("axis").Vector(symmetry.axis.normalized());
      json.Key("offset").Vector(symmetry.offset_m * kMillimetresPerMetre).Close('}');
    }
    json.Close(']');
  }
}

}  // namespace

double MeshDiameter(const TriangleMesh& mesh) {
  double longest = 0;
  const auto& v = mesh.vertices;
  for (size_t i = 0; i < v.size(); ++i) {
    for (size_t j = i + 1; j < v.size(); ++j) {
      longest = std::max(longest, double((v[i] - v[j]).squaredNorm()));
    }
  }
  return std::sqrt(longest);
}

StatusOr<std::string> ModelsInfoJson(const std::vector<PartModel>& parts) {
  std::vector<const PartModel*> sorted;
  std::set<uint32_t> ids;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string path = "parts[" + std::to_string(i) + "]";
    if (parts[i].obj_id == 0) return InvalidArgument(path + ".obj_id", "part types count from 1");
    if (!ids.insert(parts[i].obj_id).second) return InvalidArgument(path + ".obj_id", "appears twice");
    if (parts[i].mesh.vertices.empty()) return InvalidArgument(path + ".mesh", "has no vertices");
    sorted.push_back(&parts[i]);
  }
  std::sort(sorted.begin(), sorted.end(), [](const auto* a, const auto* b) { return a->obj_id < b->obj_id; });
  JsonWriter json;
  json.Open('{');
  for (const PartModel* part : sorted) {
    Eigen::Vector3f min, max;
    part->mesh.Bounds(min, max);
    const Eigen::Vector3d min_mm = min.cast<double>() * kMillimetresPerMetre;
    const Eigen::Vector3d size_mm = (max - min).cast<double>() * kMillimetresPerMetre;
    json.Key(std::to_string(part->obj_id)).Open('{');
    json.Key("diameter").Value(MeshDiameter(part->mesh) * kMillimetresPerMetre);
    json.Key("min_x").Value(min_mm.x()).Key("min_y").Value(min_mm.y()).Key("min_z").Value(min_mm.z());
    json.Key("size_x").Value(size_mm.x()).Key("size_y").Value(size_mm.y()).Key("size_z").Value(size_mm.z());
    WriteSymmetries(json, *part);
    json.Close('}');
  }
  json.Close('}');
  return json.str() + "\n";
}

}  // namespace vscan::service::dataset
