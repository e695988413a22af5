#include "service/bins/bin_fill_report.h"

#include "service/job/json_writer.h"

namespace vscan::service {
namespace {

void WriteTypes(const BinFillPlan& plan, JsonWriter& json) {
  json.Key("types").Open('[');
  for (size_t i = 0; i < plan.parts.size(); ++i) {
    const BinPartRequest& asked = plan.request.parts[i];
    json.Open('{');
    json.Key("type").Value(uint64_t{i});
    json.Key("name").Value(plan.parts[i].name);
    json.Key("mesh_id").Value(asked.mesh_id);
    json.Key("count").Value(uint64_t{asked.count});
    json.Key("source_unit").Value(UnitName(plan.meshes[i].source_unit));
    json.Key("scale").Value(asked.scale);
    json.Key("mass_kg").Value(plan.geometry[i].mass_kg);
    json.Key("collision").Value(plan.parts[i].collision == physics::PartCollision::kConvexDecomposition
                                    ? "convex_decomposition"
                                    : "convex_hull");
    json.Close('}');
  }
  json.Close(']');
}

void WriteBin(const BinFillPlan& plan, const BinFillReport& report, JsonWriter& json) {
  const physics::BinSpec& bin = plan.request.bin;
  json.Key("bin").Open('{');
  if (plan.request.mesh_bin) {
    const physics::BinInterior interior = physics::InteriorOf(bin);
    json.Key("mesh_id").Value(plan.request.bin_mesh_id);
    json.Key("scale").Value(plan.request.bin_mesh_scale);
    json.Key("bounds_min").Vector(interior.lo);
    json.Key("bounds_max").Vector(interior.hi);
  } else {
    json.Key("inner_size").Vector(bin.inner_size);
    json.Key("wall_thickness").Value(bin.wall_thickness);
  }
  json.Key("world_from_bin").Matrix(bin.world_from_bin);
  if (report.placement) {
    json.Key("object_id").Value(report.placement->bin.object_id);
    json.Key("instance_id").Value(uint64_t{report.placement->bin.instance_id});
    if (!plan.request.mesh_bin) json.Key("mesh_id").Value(report.placement->bin.mesh_id);
    json.Key("label").Value(report.placement->bin.label);
  }
  json.Close('}');
}

void WriteParts(const BinFillPlan& plan, const BinFillReport& report, JsonWriter& json) {
  const physics::FillResult& result = *report.result;
  json.Key("parts").Open('[');
  for (size_t i = 0; i < result.parts.size(); ++i) {
    const physics::PlacedPart& part = result.parts[i];
    json.Open('{');
    json.Key("type").Value(uint64_t{part.type});
    json.Key("name").Value(plan.parts[part.type].name);
    json.Key("instance").Value(uint64_t{part.instance});
    json.Key("mesh_id").Value(plan.request.parts[part.type].mesh_id);
    json.Key("source_unit").Value(UnitName(plan.meshes[part.type].source_unit));
    json.Key("scale").Value(plan.request.parts[part.type].scale);
    if (report.placement) {
      const store::ObjectRecord& object = report.placement->parts[i];
      json.Key("object_id").Value(object.object_id);
      json.Key("instance_id").Value(uint64_t{object.instance_id});
      json.Key("label").Value(object.label);
    } else {
      json.Key("label").Value(PartLabel(plan.parts[part.type].name, part.instance));
    }
    json.Key("world_from_part").Matrix(part.world_from_part);
    json.Close('}');
  }
  json.Close(']');
  json.Key("outside").Open('[');
  for (const physics::PlacedPart& part : result.outside) {
    json.Open('{');
    json.Key("type").Value(uint64_t{part.type});
    json.Key("name").Value(plan.parts[part.type].name);
    json.Key("instance").Value(uint64_t{part.instance});
    json.Close('}');
  }
  json.Close(']');
}

}  // namespace

void WriteMeshOverlap(const physics::MeshOverlaps& overlap, JsonWriter& json) {
  json.Open('{');
  json.Key("max_part_part_m").Value(overlap.max_part_part_m);
  json.Key("p95_part_part_m").Value(overlap.p95_part_part_m);
  json.Key("overlapping_pairs").Value(uint64_t{overlap.overlapping_pairs});
  json.Key("max_part_bin_m").Value(overlap.max_part_bin_m);
  json.Key("resolution_m").Value(overlap.resolution_m);
  json.Close('}');
}

const char* UnitName(store::LengthUnit unit) {
  switch (unit) {
    case store::LengthUnit::kMetre: return "m";
    case store::LengthUnit::kCentimetre: return "cm";
    case store::LengthUnit::kMillimetre: return "mm";
    case store::LengthUnit::kInch: return "in";
    case store::LengthUnit::kFoot: return "ft";
    case store::LengthUnit::kUnspecified: break;
  }
  return "";
}

std::string BinFillJson(const BinFillPlan& plan, const BinFillReport& report) {
  JsonWriter json;
  json.Open('{');
  json.Key("job_id").Value(report.job_id);
  json.Key("name").Value(plan.request.name);
  json.Key("scene_id").Value(plan.request.scene_id);
  json.Key("state").Value(store::JobStateName(report.state));
  json.Key("message").Value(report.message);
  json.Key("seed").Value(plan.request.options.seed);
  const physics::FillOptions& options = plan.request.options;
  json.Key("physics").Open('{');
  json.Key("max_simulated_s").Value(options.max_simulated_s);
  json.Key("time_step_s").Value(options.time_step_s);
  json.Key("settle_move_m").Value(options.settle_move_m);
  json.Key("settle_turn_rad").Value(options.settle_turn_rad);
  json.Key("settle_steps").Value(static_cast<uint64_t>(options.settle_steps));
  json.Close('}');
  json.Key("applied").Value(report.placement.has_value());
  if (report.placement) json.Key("scene_revision").Value(report.placement->revision);
  WriteBin(plan, report, json);
  WriteTypes(plan, json);
  json.Key("parts_asked").Value(uint64_t{plan.parts_total()});
  if (report.result) {
    const physics::FillResult& result = *report.result;
    json.Key("end").Value(physics::FillEndName(result.end));
    json.Key("end_message").Value(result.message);
    json.Key("spawned").Value(uint64_t{result.spawned});
    json.Key("in_bin").Value(uint64_t{result.parts.size()});
    json.Key("simulated_s").Value(result.simulated_s);
    json.Key("steps").Value(result.steps);
    json.Key("max_part_part_penetration_m").Value(result.max_part_part_penetration_m);
    json.Key("max_part_bin_penetration_m").Value(result.max_part_bin_penetration_m);
    json.Key("mesh_overlap");
    WriteMeshOverlap(result.mesh_overlap, json);
    json.Key("setup_wall_s").Value(result.setup_wall_s);
    json.Key("step_wall_s").Value(result.step_wall_s);
    WriteParts(plan, report, json);
  }
  json.Close('}');
  return json.str() + "\n";
}

}  // namespace vscan::service
