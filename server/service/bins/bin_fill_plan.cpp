#include "service/bins/bin_fill_plan.h"

#include <string>

#include "physics/fill_checks.h"
#include "vscan/common/physical_limits.h"

namespace vscan::service {
namespace {

std::string PartField(size_t i, const char* member) { return "parts[" + std::to_string(i) + "]." + member; }

// The stored mesh (metres) times the part's scale: the part's own frame for the physics.
StatusOr<TriangleMesh> ScaledPart(scenes::SceneRegistry& registry, const BinPartRequest& part, size_t i) {
  ASSIGN_OR_RETURN(const auto loaded, registry.LoadMesh(part.mesh_id));
  return physics::ScalePart(*loaded, part.scale, "parts[" + std::to_string(i) + "]");
}

// The stored bin mesh (metres) times its scale: the bin frame for the physics.
StatusOr<TriangleMesh> ScaledBin(scenes::SceneRegistry& registry, const std::string& mesh_id, double scale) {
  auto record = registry.catalogue().GetMesh(mesh_id);
  if (!record.ok() && record.status().code() == StatusCode::kNotFound) {
    return NotFound("bin_mesh.mesh_id", "no mesh '" + mesh_id + "'");
  }
  RETURN_IF_ERROR(record.status());
  ASSIGN_OR_RETURN(const auto loaded, registry.LoadMesh(mesh_id));
  TriangleMesh mesh = *loaded;
  for (Eigen::Vector3f& v : mesh.vertices) v *= static_cast<float>(scale);
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  const Eigen::Vector3f size = hi - lo;
  if (!(size.minCoeff() >= 1e-3f && size.maxCoeff() <= 100.0f)) {
    return InvalidArgument("bin_mesh.scale", "the bin scaled by " + std::to_string(scale) + " is " +
                                                 std::to_string(size.x()) + " x " + std::to_string(size.y()) + " x " +
                                                 std::to_string(size.z()) +
                                                 " m; a bin must be 1 mm to 100 m on every side (it must hold a volume)");
  }
  return mesh;
}

}  // namespace

size_t BinFillPlan::parts_total() const {
  size_t total = 0;
  for (const auto& part : parts) total += part.count;
  return total;
}

StatusOr<BinFillPlan> PlanBinFill(scenes::SceneRegistry& registry, BinFillRequest request, bool validate_only) {
  if (!request.scene_id.empty() || !validate_only) {
    RETURN_IF_ERROR(registry.catalogue().GetScene(request.scene_id).status());
  }
  bool every_mesh = true;
  if (request.mesh_bin && request.bin_mesh_id.empty() && validate_only) {
    every_mesh = false;
  } else if (request.mesh_bin) {
    ASSIGN_OR_RETURN(request.bin.mesh, ScaledBin(registry, request.bin_mesh_id, request.bin_mesh_scale));
  }
  // Every corner of the bin must stay within the bounds where meshes may lie.
  if (every_mesh) {
    const bool mesh_bin = request.mesh_bin;
    const physics::BinInterior interior = physics::InteriorOf(request.bin);
    // The box is centred on its frame; a mesh may lie anywhere in it.
    const double extent = mesh_bin ? interior.lo.cwiseAbs().cwiseMax(interior.hi.cwiseAbs()).norm()
                                   : (interior.hi - interior.lo + Eigen::Vector3d::Constant(2 * interior.wall)).norm();
    const double reach = request.bin.world_from_bin.translation().cwiseAbs().maxCoeff() + extent;
    if (!(reach <= kMaxMeshCoordinateM)) {
      return InvalidArgument(mesh_bin ? "bin_mesh.pose" : "bin.pose",
                             "the bin reaches " + std::to_string(reach) + " m from the origin; at most 1e4 m");
    }
  }
  BinFillPlan plan;
  for (size_t i = 0; i < request.parts.size(); ++i) {
    const BinPartRequest& asked = request.parts[i];
    if (asked.mesh_id.empty() && validate_only) {
      every_mesh = false;
      continue;
    }
    auto record = registry.catalogue().GetMesh(asked.mesh_id);
    if (!record.ok() && record.status().code() == StatusCode::kNotFound) {
      return NotFound(PartField(i, "mesh_id"), "no mesh '" + asked.mesh_id + "'");
    }
    RETURN_IF_ERROR(record.status());
    physics::PartType part;
    ASSIGN_OR_RETURN(part.mesh, ScaledPart(registry, asked, i));
    part.name = asked.name.empty() ? record->name : asked.name;
    part.count = asked.count;
    part.mass_kg = asked.mass_kg;
    part.density_kg_per_m3 = asked.density_kg_per_m3;
    part.collision = asked.collision;
    plan.parts.push_back(std::move(part));
    plan.meshes.push_back(std::move(record).value());
  }
  // A plan checked before its meshes are uploaded is complete but for them.
  if (!every_mesh) {
    plan.request = std::move(request);
    return plan;
  }
  RETURN_IF_ERROR(physics::CheckFillInput(request.bin, plan.parts, request.options));
  // Hulls only: a convex decomposition (up to seconds of cuts on a large mesh) is made on the job's own
  // thread when the fill starts, never on the threads that answer calls.
  std::vector<physics::PartType> hulls = plan.parts;
  for (physics::PartType& part : hulls) part.collision = physics::PartCollision::kConvexHull;
  plan.geometry = physics::MakePartGeometries(hulls, request.options.hull_tolerance_m);
  RETURN_IF_ERROR(physics::CheckPartMasses(plan.geometry));
  plan.request = std::move(request);
  return plan;
}

}  // namespace vscan::service
