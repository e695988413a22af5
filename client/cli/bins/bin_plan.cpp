#include "bins/bin_plan.h"

#include "campaign/plan_values.h"
#include "campaign/yaml_messages.h"
#include "session/args.h"
#include "vscan/common/proto_convert.h"
#include "vscan/plan/bin_fill_plan.h"

namespace vscan::cli {
namespace {

class BinPlanParser {
 public:
  BinPlanParser(const std::string& source, std::filesystem::path base_dir)
      : yaml_(source), base_dir_(std::move(base_dir)), default_name_(std::filesystem::path(source).stem().string()) {}

  StatusOr<BinPlan> Parse(const YAML::Node& root) {
    const YamlAt top{root, "", root.Mark()};
    if (!root.IsMap()) return yaml_.Error(top, "a bin plan is a mapping with keys name, scene, bin, parts, ...");
    RETURN_IF_ERROR(yaml_.ExpectMap(top, {"name", "scene", "scene_id", "bin", "parts", "seed", "physics", "picks"}));
    BinPlan plan;
    plan.name = default_name_;
    if (const YamlAt at = YamlReader::Child(top, "name"); YamlReader::Has(at)) {
      ASSIGN_OR_RETURN(plan.name, yaml_.String(at));
    }
    plan.spec.set_name(plan.name);
    RETURN_IF_ERROR(ParseScene(top, &plan));
    RETURN_IF_ERROR(ParseFill(top, &plan));
    if (const YamlAt seed = YamlReader::Child(top, "seed"); YamlReader::Has(seed)) {
      ASSIGN_OR_RETURN(const uint64_t value, yaml_.Integer(seed, 0, UINT64_MAX));
      plan.spec.set_seed(value);
    }
    if (const YamlAt physics = YamlReader::Child(top, "physics"); YamlReader::Has(physics)) {
      RETURN_IF_ERROR(FillMessage(yaml_, physics, plan.spec.mutable_physics()));
    }
    // The pick check after the fill: mount_id, gripper, grasp_options, pick_options (spec.picks).
    if (const YamlAt picks = YamlReader::Child(top, "picks"); YamlReader::Has(picks)) {
      RETURN_IF_ERROR(FillMessage(yaml_, picks, plan.spec.mutable_picks()));
    }
    return plan;
  }

 private:
  Status ParseScene(const YamlAt& top, BinPlan* plan) const {
    const YamlAt scene = YamlReader::Child(top, "scene");
    const YamlAt id = YamlReader::Child(top, "scene_id");
    if (YamlReader::Has(scene) && YamlReader::Has(id)) return yaml_.Error(id, "give either scene or scene_id, not both");
    if (YamlReader::Has(id)) {
      ASSIGN_OR_RETURN(plan->scene_id, yaml_.String(id));
    } else if (YamlReader::Has(scene)) {
      ASSIGN_OR_RETURN(plan->scene_name, yaml_.String(scene));
    } else {
      return yaml_.Error(top.mark, "scene", "required: a scene name (created when no scene has it) or scene_id");
    }
    return Status::Ok();
  }

  // The plan's mesh source with its file found from the plan's directory and its unit as the wire's.
  StatusOr<BinPlanPart> Resolve(const plan::MeshSource& source) const {
    BinPlanPart part;
    if (source.file.empty()) {
      part.mesh_id = source.mesh_id;
      return part;
    }
    part.mesh = (base_dir_ / source.file).lexically_normal();
    std::error_code ec;
    if (!std::filesystem::exists(part.mesh, ec)) {
      return yaml_.Error(source.mark, source.key, "no such file or directory: " + part.mesh.string());
    }
    ASSIGN_OR_RETURN(part.unit, ParseUnit(source.unit));
    return part;
  }

  Status ParseFill(const YamlAt& top, BinPlan* plan) const {
    const YamlAt bin_at = YamlReader::Child(top, "bin");
    ASSIGN_OR_RETURN(const plan::BinFillPlan fill, plan::ReadBinFill(yaml_, bin_at, YamlReader::Child(top, "parts")));
    if (fill.box) {
      v1::BinBox* bin = plan->spec.mutable_bin();
      *bin->mutable_inner_size() = ToProto(fill.box->inner_size);
      if (fill.box->wall_thickness) bin->set_wall_thickness(*fill.box->wall_thickness);
    } else {
      v1::BinMesh* bin = plan->spec.mutable_bin_mesh();
      if (fill.mesh_bin->scale) bin->set_scale(*fill.mesh_bin->scale);
      ASSIGN_OR_RETURN(plan->bin_mesh, Resolve(fill.mesh_bin->mesh));
    }
    if (const YamlAt pose_at = YamlReader::Child(bin_at, "pose"); YamlReader::Has(pose_at)) {
      ASSIGN_OR_RETURN(const v1::Pose pose, ReadPlanPose(yaml_, pose_at));
      *(fill.box ? plan->spec.mutable_bin()->mutable_pose() : plan->spec.mutable_bin_mesh()->mutable_pose()) = pose;
    }
    for (size_t i = 0; i < fill.parts.size(); ++i) {
      const plan::PartPlan& part = fill.parts[i];
      if (!part.material_choices.empty()) {
        return yaml_.Error(part.material_mark, "parts[" + std::to_string(i) + "].material",
                           "a bin fill takes one material; choose is for dataset plans");
      }
      v1::BinPart* spec = plan->spec.add_parts();
      ASSIGN_OR_RETURN(BinPlanPart source, Resolve(part.mesh));
      spec->set_count(part.count);
      if (part.scale) spec->set_scale(*part.scale);
      if (!part.name.empty()) {
        spec->set_name(part.name);
      } else if (!source.mesh.empty()) {
        spec->set_name(source.mesh.stem().string());
      }
      if (part.mass_kg) spec->set_mass_kg(*part.mass_kg);
      if (part.density_kg_per_m3) spec->set_density_kg_per_m3(*part.density_kg_per_m3);
      if (part.collision == "convex_hull") spec->set_collision(v1::PART_COLLISION_CONVEX_HULL);
      if (part.collision == "convex_decomposition") spec->set_collision(v1::PART_COLLISION_CONVEX_DECOMPOSITION);
      if (part.material) *spec->mutable_material() = MaterialMessage(*part.material);
      plan->parts.push_back(std::move(source));
    }
    return Status::Ok();
  }

  YamlReader yaml_;
  std::filesystem::path base_dir_;
  std::string default_name_;
};

}  // namespace

StatusOr<BinPlan> ParseBinPlan(const std::string& yaml, const std::string& source,
                               const std::filesystem::path& base_dir) {
  return ParsePlanDocument<BinPlan>(
      yaml, source, [&](const YAML::Node& root) { return BinPlanParser(source, base_dir).Parse(root); });
}

StatusOr<BinPlan> LoadBinPlan(const std::string& path) {
  ASSIGN_OR_RETURN(const std::string text, ReadPlanFile(path));
  return ParseBinPlan(text, path, std::filesystem::path(path).parent_path());
}

std::optional<std::string> LocateInBinPlan(const BinPlan& plan, const Status& status) {
  if (status.ok() || !NamesAField(status.code())) return std::nullopt;
  const std::string& message = status.message();
  if (!message.starts_with("spec.")) return std::nullopt;
  const size_t colon = message.find(": ");
  if (colon == std::string::npos) return std::nullopt;
  const std::string field = message.substr(5, colon - 5);
  // The plan writes a mesh bin under bin: like the box.
  std::string at = field.starts_with("bin_mesh") ? "bin" + field.substr(8) : field;
  // A part's mesh_id comes from its mesh file when the plan names one.
  if (at.ends_with(".mesh_id") && !plan.key_marks.contains(at)) at = ParentKey(at) + ".mesh";
  while (!at.empty() && !plan.key_marks.contains(at)) at = ParentKey(at);
  const auto mark = plan.key_marks.find(at);
  if (mark == plan.key_marks.end()) return std::nullopt;
  return plan.source + ":" + std::to_string(mark->second.line + 1) + ": " + field + ": " + message.substr(colon + 2);
}

}  // namespace vscan::cli
