#include "api/bins/bin_fill_spec.h"

#include <cmath>
#include <string>

#include "api/bins/bin_picks_spec.h"
#include "api/campaign/campaign_spec.h"
#include "api/scenes/material_convert.h"
#include "api/transport/validate.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr double kMinBinSideM = 1e-3;
constexpr double kMaxBinSideM = 100;
constexpr double kMaxWallM = 10;
constexpr double kMaxSimulatedS = 600;
constexpr int kMaxPartTypes = 64;

std::string Num(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", x);
  return buffer;
}


Status ReadBinMesh(const v1::BinMesh& in, bool validate_only, service::BinFillRequest& request) {
  if (!validate_only || !in.mesh_id().empty()) RETURN_IF_ERROR(RequireId(in.mesh_id(), "bin_mesh.mesh_id"));
  request.mesh_bin = true;
  request.bin_mesh_id = in.mesh_id();
  ASSIGN_OR_RETURN(request.bin_mesh_scale, ScaleOrDefault(in.scale(), "bin_mesh.scale"));
  if (in.has_pose()) {
    ASSIGN_OR_RETURN(request.bin.world_from_bin, PoseFromProto(in.pose(), "bin_mesh.pose"));
  }
  return Status::Ok();
}

Status ReadBin(const v1::BinFillSpec& spec, physics::BinSpec& bin) {
  if (!spec.has_bin()) return InvalidArgument("bin", "required (or bin_mesh)");
  if (!spec.bin().has_inner_size()) return InvalidArgument("bin.inner_size", "required");
  const Eigen::Vector3d size = FromProto(spec.bin().inner_size());
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(size[k]) || size[k] < kMinBinSideM || size[k] > kMaxBinSideM) {
      return InvalidArgument("bin.inner_size", "each side must be finite and within [1 mm, 100 m], got " +
                                                   Num(size.x()) + " x " + Num(size.y()) + " x " + Num(size.z()) +
                                                   " m");
    }
  }
  bin.inner_size = size;
  ASSIGN_OR_RETURN(bin.wall_thickness,
                   NumberOrDefault(spec.bin().wall_thickness(), 0.01, 1e-4, kMaxWallM, "bin.wall_thickness", "m"));
  if (spec.bin().has_pose()) {
    ASSIGN_OR_RETURN(bin.world_from_bin, PoseFromProto(spec.bin().pose(), "bin.pose"));
  }
  return Status::Ok();
}

StatusOr<physics::PartCollision> Collision(int value, const std::string& field) {
  switch (value) {
    case v1::PART_COLLISION_UNSPECIFIED:
    case v1::PART_COLLISION_CONVEX_HULL: return physics::PartCollision::kConvexHull;
    case v1::PART_COLLISION_CONVEX_DECOMPOSITION: return physics::PartCollision::kConvexDecomposition;
    default: break;
  }
  return InvalidArgument(field, "unknown value " + std::to_string(value));
}

Status ReadParts(const v1::BinFillSpec& spec, bool validate_only, std::vector<service::BinPartRequest>& parts) {
  if (spec.parts_size() == 0) return InvalidArgument("parts", "name at least one part type");
  if (spec.parts_size() > kMaxPartTypes) {
    return InvalidArgument("parts", "at most " + std::to_string(kMaxPartTypes) + " part types, not " +
                                        std::to_string(spec.parts_size()));
  }
  uint64_t total = 0;
  for (int i = 0; i < spec.parts_size(); ++i) {
    const v1::BinPart& in = spec.parts(i);
    const std::string field = "parts[" + std::to_string(i) + "]";
    service::BinPartRequest part;
    if (!validate_only || !in.mesh_id().empty()) RETURN_IF_ERROR(RequireId(in.mesh_id(), field + ".mesh_id"));
    part.mesh_id = in.mesh_id();
    if (in.count() == 0) return InvalidArgument(field + ".count", "must be at least 1");
    total += in.count();
    if (total > physics::kMaxFillParts) {
      return InvalidArgument(field + ".count", "all counts together at most " +
                                                   std::to_string(physics::kMaxFillParts) + ", got " +
                                                   std::to_string(total) + " so far");
    }
    part.count = in.count();
    ASSIGN_OR_RETURN(part.scale, ScaleOrDefault(in.scale(), field + ".scale"));
    ASSIGN_OR_RETURN(part.collision, Collision(in.collision(), field + ".collision"));
    RETURN_IF_ERROR(CheckText(in.name(), field + ".name"));
    part.name = in.name();
    if (in.mass_kg() != 0) {
      ASSIGN_OR_RETURN(const double mass, NumberOrDefault(in.mass_kg(), 0, 1e-6, 1e4, field + ".mass_kg", "kg"));
      part.mass_kg = mass;
    }
    ASSIGN_OR_RETURN(part.density_kg_per_m3,
                     NumberOrDefault(in.density_kg_per_m3(), 2700, 1, 1e5, field + ".density_kg_per_m3", "kg/m^3"));
    ASSIGN_OR_RETURN(part.material, OptionalMaterialFromProto(in.has_material(), in.material(), field + ".material"));
    parts.push_back(std::move(part));
  }
  return Status::Ok();
}

Status ReadPhysics(const v1::BinPhysics& in, physics::FillOptions& options) {
  ASSIGN_OR_RETURN(options.max_simulated_s,
                   NumberOrDefault(in.max_simulated_s(), options.max_simulated_s, 0.01, kMaxSimulatedS,
                             "physics.max_simulated_s", "s"));
  ASSIGN_OR_RETURN(options.settle_move_m,
                   NumberOrDefault(in.settle_move_m(), options.settle_move_m, 1e-7, 1, "physics.settle_move_m", "m"));
  ASSIGN_OR_RETURN(options.settle_turn_rad,
                   NumberOrDefault(in.settle_turn_rad(), options.settle_turn_rad, 1e-7, 3.14159, "physics.settle_turn_rad",
                             "rad"));
  if (in.settle_steps() > 100000) {
    return InvalidArgument("physics.settle_steps", "at most 100000, got " + std::to_string(in.settle_steps()));
  }
  if (in.settle_steps() != 0) options.settle_steps = static_cast<int>(in.settle_steps());
  ASSIGN_OR_RETURN(options.time_step_s,
                   NumberOrDefault(in.time_step_s(), options.time_step_s, 1e-4, 0.05, "physics.time_step_s", "s"));
  return Status::Ok();
}

}  // namespace

StatusOr<service::BinFillRequest> BinFillRequestFromProto(const v1::BinFillSpec& spec, bool validate_only) {
  service::BinFillRequest request;
  if (!spec.scene_id().empty()) RETURN_IF_ERROR(RequireId(spec.scene_id(), "scene_id"));
  request.scene_id = spec.scene_id();
  RETURN_IF_ERROR(CheckText(spec.name(), "name"));
  request.name = spec.name();
  if (spec.has_bin() && spec.has_bin_mesh()) return InvalidArgument("bin_mesh", "give bin or bin_mesh, not both");
  if (spec.has_bin_mesh()) {
    RETURN_IF_ERROR(ReadBinMesh(spec.bin_mesh(), validate_only, request));
  } else {
    RETURN_IF_ERROR(ReadBin(spec, request.bin));
  }
  RETURN_IF_ERROR(ReadParts(spec, validate_only, request.parts));
  RETURN_IF_ERROR(ReadPhysics(spec.physics(), request.options));
  request.options.seed = spec.seed();
  return request;
}

StatusOr<service::BinFillPlan> ValidateBinFill(const v1::BinFillSpec& spec, service::ServiceContext& context,
                                               bool validate_only) {
  auto request = BinFillRequestFromProto(spec, validate_only);
  if (!request.ok()) return InSpec(request.status());
  if (request->scene_id.empty() && !validate_only) return InSpec(InvalidArgument("scene_id", "required"));
  auto plan = service::PlanBinFill(context.registry, std::move(request).value(), validate_only);
  if (!plan.ok()) return InSpec(plan.status());
  if (spec.has_picks()) RETURN_IF_ERROR(InSpec(AddBinPickCheck(spec.picks(), context, *plan)));
  return plan;
}

}  // namespace vscan::api
