#pragma once
// A bin fill as the service runs it: the bin, the part types with their meshes loaded and
// scaled, and the physics options, checked against what the server holds.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "physics/bin_fill.h"
#include "physics/part_geometry.h"
#include "service/bins/bin_picks.h"
#include "scenes/scene_registry.h"
#include "store/catalogue.h"

namespace vscan::service {

struct BinPartRequest {
  std::string mesh_id;
  uint32_t count = 0;
  double scale = 1.0;
  std::string name;  // empty: the mesh's name
  std::optional<double> mass_kg;
  double density_kg_per_m3 = 2700.0;
  physics::PartCollision collision = physics::PartCollision::kConvexHull;
  // Each placed part's material override (unset: the mesh's).
  std::optional<store::MaterialRecord> material;
};

// What a request asks, its values already checked (api/bin_fill_spec.cpp).
struct BinFillRequest {
  std::string scene_id;
  std::string name;  // the bin object's label and the job's name
  physics::BinSpec bin;  // its mesh is loaded by PlanBinFill
  // A mesh bin (the stored mesh bin_mesh_id, scaled) instead of the box.
  bool mesh_bin = false;
  std::string bin_mesh_id;
  double bin_mesh_scale = 1.0;
  std::vector<BinPartRequest> parts;
  physics::FillOptions options;
};

struct BinFillPlan {
  BinFillRequest request;
  // parts[i]: the mesh scaled into the part's frame, named and counted as asked.
  std::vector<physics::PartType> parts;
  std::vector<store::MeshRecord> meshes;
  // What the physics needs of each part (centre of mass, mass, simplified hull), made once here;
  // convex decompositions are made when the fill runs (SimulateBinFill).
  std::vector<physics::PartGeometry> geometry;
  // Set when the request asks for picks (spec.picks): run on the placed parts.
  BinPickCheck pick_check;
  size_t parts_total() const;
};

// Looks up the scene and the meshes (NOT_FOUND naming "scene_id", "bin_mesh.mesh_id" or
// "parts[i].mesh_id"), loads a mesh bin into request.bin.mesh and
// checks the scaled parts against the physical bounds. validate_only skips the scene and the
// meshes whose ids are empty (the plan then lacks those parts).
StatusOr<BinFillPlan> PlanBinFill(scenes::SceneRegistry& registry, BinFillRequest request, bool validate_only = false);

}  // namespace vscan::service
