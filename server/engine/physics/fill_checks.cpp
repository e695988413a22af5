#include "physics/fill_checks.h"

#include <cmath>
#include <string>

namespace vscan::physics {
namespace {

bool Positive(double v) { return std::isfinite(v) && v > 0; }
bool NonNegative(double v) { return std::isfinite(v) && v >= 0; }

Status Bad(const std::string& field, const std::string& text) {
  return {StatusCode::kInvalidArgument, field, text};
}

Status CheckBinMesh(const TriangleMesh& mesh) {
  for (const Eigen::Vector3f& v : mesh.vertices) {
    if (!v.allFinite()) return Bad("bin.mesh", "has a vertex that is not finite");
  }
  for (const auto& t : mesh.triangles) {
    for (uint32_t i : t) {
      if (i >= mesh.vertices.size()) return Bad("bin.mesh", "has a vertex index out of range");
    }
  }
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  const Eigen::Vector3f size = hi - lo;
  if (size.minCoeff() < 1e-3f || size.maxCoeff() > 100.0f) {
    return Bad("bin.mesh", "its bounding box must be 1 mm to 100 m on every side (a bin must hold a volume), got " +
                               std::to_string(size.x()) + " x " + std::to_string(size.y()) + " x " +
                               std::to_string(size.z()) + " m");
  }
  return Status::Ok();
}

Status CheckBin(const BinSpec& bin) {
  if (!bin.mesh.empty()) {
    RETURN_IF_ERROR(CheckBinMesh(bin.mesh));
  } else if (!bin.inner_size.allFinite() || (bin.inner_size.array() <= 0).any() || (bin.inner_size.array() > 100).any()) {
    return Bad("bin.inner_size", "each side must be finite, positive and at most 100 m");
  } else if (!Positive(bin.wall_thickness) || bin.wall_thickness > 10) {
    return Bad("bin.wall_thickness", "must be finite, positive and at most 10 m");
  }
  if (!bin.world_from_bin.matrix().allFinite()) return Bad("bin.world_from_bin", "must be finite");
  const Eigen::Matrix3d r = bin.world_from_bin.linear();
  if (!(r * r.transpose()).isIdentity(1e-6) || r.determinant() < 0) {
    return Bad("bin.world_from_bin", "must be a rigid transform");
  }
  return Status::Ok();
}

Status CheckPart(const PartType& part, const std::string& field) {
  if (part.mesh.empty()) return Bad(field + ".mesh", "has no triangles");
  for (const Eigen::Vector3f& v : part.mesh.vertices) {
    if (!v.allFinite()) return Bad(field + ".mesh", "has a vertex that is not finite");
  }
  for (const auto& t : part.mesh.triangles) {
    for (uint32_t i : t) {
      if (i >= part.mesh.vertices.size()) return Bad(field + ".mesh", "has a vertex index out of range");
    }
  }
  Eigen::Vector3f lo, hi;
  part.mesh.Bounds(lo, hi);
  if ((hi - lo).maxCoeff() <= 0 || (hi - lo).maxCoeff() > 10) {
    return Bad(field + ".mesh", "must be larger than a point and at most 10 m across (metres)");
  }
  if (part.count > kMaxFillParts) {
    return Bad(field + ".count", "at most " + std::to_string(kMaxFillParts) + " parts");
  }
  if (part.collision == PartCollision::kConvexDecomposition && part.mesh.triangles.size() > kMaxDecompositionTriangles) {
    return {StatusCode::kResourceExhausted, field + ".mesh",
            "convex decomposition takes meshes of at most " + std::to_string(kMaxDecompositionTriangles) +
                " triangles (its time grows with them and it cannot be stopped); this one has " +
                std::to_string(part.mesh.triangles.size()) + ": simplify it or use the convex hull"};
  }
  if (part.mass_kg && (!Positive(*part.mass_kg) || *part.mass_kg > 1e4)) {
    return Bad(field + ".mass_kg", "must be finite, positive and at most 10 t");
  }
  if (!part.mass_kg && (!Positive(part.density_kg_per_m3) || part.density_kg_per_m3 > 1e5)) {
    return Bad(field + ".density_kg_per_m3", "must be finite, positive and at most 1e5");
  }
  return Status::Ok();
}

Status CheckOptions(const FillOptions& o) {
  const auto in = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  if (!in(o.time_step_s, 1e-4, 0.05)) return Bad("options.time_step_s", "must be within [1e-4, 0.05] s");
  if (o.substeps < 1 || o.substeps > 16) return Bad("options.substeps", "must be within [1, 16]");
  if (o.solver_iterations < 1 || o.solver_iterations > 200) {
    return Bad("options.solver_iterations", "must be within [1, 200]");
  }
  if (!in(o.hull_tolerance_m, 0, 0.01)) return Bad("options.hull_tolerance_m", "must be within [0, 0.01] m");
  if (!in(o.collision_margin_m, 0, 0.05)) return Bad("options.collision_margin_m", "must be within [0, 0.05] m");
  if (!in(o.friction, 0, 10)) return Bad("options.friction", "must be within [0, 10]");
  if (!in(o.restitution, 0, 1)) return Bad("options.restitution", "must be within [0, 1]");
  if (!Positive(o.settle_move_m)) return Bad("options.settle_move_m", "must be finite and positive");
  if (!Positive(o.settle_turn_rad)) return Bad("options.settle_turn_rad", "must be finite and positive");
  if (o.settle_steps < 1 || o.settle_steps > 100000) return Bad("options.settle_steps", "must be within [1, 100000]");
  if (!in(o.settle_damping, 0, 1)) return Bad("options.settle_damping", "must be within [0, 1]");
  if (!NonNegative(o.sleep_linear_m_per_s)) return Bad("options.sleep_linear_m_per_s", "must be finite, >= 0");
  if (!NonNegative(o.sleep_angular_rad_per_s)) return Bad("options.sleep_angular_rad_per_s", "must be finite, >= 0");
  if (!in(o.rolling_friction_m, 0, 1)) return Bad("options.rolling_friction_m", "must be within [0, 1] m");
  if (!in(o.linear_damping, 0, 1)) return Bad("options.linear_damping", "must be within [0, 1]");
  if (!in(o.angular_damping, 0, 1)) return Bad("options.angular_damping", "must be within [0, 1]");
  if (!in(o.max_simulated_s, 0, 3600) || o.max_simulated_s == 0) {
    return Bad("options.max_simulated_s", "must be positive and at most 3600 s");
  }
  if (o.parts_per_drop < 1 || o.parts_per_drop > 100) return Bad("options.parts_per_drop", "must be within [1, 100]");
  if (!in(o.drop_clearance_m, 0, 10)) return Bad("options.drop_clearance_m", "must be within [0, 10] m");
  if (!Positive(o.drop_interval_s)) return Bad("options.drop_interval_s", "must be finite and positive");
  if (o.spawn_attempts < 1 || o.spawn_attempts > 10000) {
    return Bad("options.spawn_attempts", "must be within [1, 10000]");
  }
  if (!in(o.max_mesh_overlap_m, 0, 0.01)) return Bad("options.max_mesh_overlap_m", "must be within [0, 0.01] m");
  if (o.separation_rounds < 0 || o.separation_rounds > 100) {
    return Bad("options.separation_rounds", "must be within [0, 100]");
  }
  if (!NonNegative(o.rim_tolerance_m)) return Bad("options.rim_tolerance_m", "must be finite and not negative");
  return Status::Ok();
}

}  // namespace

Status CheckFillInput(const BinSpec& bin, const std::vector<PartType>& parts, const FillOptions& options) {
  RETURN_IF_ERROR(CheckBin(bin));
  if (parts.empty()) return Bad("parts", "name at least one part type");
  size_t total = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string field = "parts[" + std::to_string(i) + "]";
    RETURN_IF_ERROR(CheckPart(parts[i], field));
    total += parts[i].count;
    if (total > kMaxFillParts) {
      return Bad(field + ".count", "all counts together at most " + std::to_string(kMaxFillParts));
    }
  }
  return CheckOptions(options);
}

StatusOr<TriangleMesh> ScalePart(TriangleMesh mesh, double scale, const std::string& field) {
  for (Eigen::Vector3f& v : mesh.vertices) v *= static_cast<float>(scale);
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  const double across = static_cast<double>((hi - lo).maxCoeff());
  if (!(across >= 1e-3 && across <= 10)) {
    return Bad(field + ".scale", "the part scaled by " + std::to_string(scale) + " is " + std::to_string(across) +
                                     " m across; parts must be 1 mm to 10 m");
  }
  return mesh;
}

Status CheckPartMasses(const std::vector<PartGeometry>& geometry) {
  for (size_t i = 0; i < geometry.size(); ++i) {
    if (!(geometry[i].mass_kg > 0)) {
      return Bad("parts[" + std::to_string(i) + "].mass_kg", "the mesh encloses no volume: give a mass");
    }
  }
  return Status::Ok();
}

}  // namespace vscan::physics
