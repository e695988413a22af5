#include "bins/bin_plan.h"


#include "campaign/campaign_yaml.h"
#include "campaign/plan_values.h"
#include "session/args.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

constexpr uint64_t kMaxCount = 100000;

class BinPlanParser {
 public:
  BinPlanParser(const std::string& source, std::filesystem::path base_dir)
      : yaml_(source), base_dir_(std::move(base_dir)), default_name_(std::filesystem::path(source).stem().string()) {}

  StatusOr<BinPlan> Parse(const YAML::Node& root) {
    const YamlAt top{root, "", root.Mark()};
    if (!root.IsMap()) return yaml_.Error(top, "a bin plan is a mapping with keys name, scene, bin, parts, ...");
    RETURN_IF_ERROR(yaml_.ExpectMap(top, {"name", "scene", "scene_id", "bin", "parts", "seed", "physics"}));
    BinPlan plan;
    plan.name = default_name_;
    if (const YamlAt at = YamlReader::Child(top, "name"); YamlReader::Has(at)) {
      ASSIGN_OR_RETURN(plan.name, yaml_.String(at));
    }
    plan.spec.set_name(plan.name);
    RETURN_IF_ERROR(ParseScene(top, &plan));
    RETURN_IF_ERROR(ParseBin(YamlReader::Child(top, "bin"), &plan));
    RETURN_IF_ERROR(ParseParts(YamlReader::Child(top, "parts"), &plan));
    if (const YamlAt seed = YamlReader::Child(top, "seed"); YamlReader::Has(seed)) {
      ASSIGN_OR_RETURN(const uint64_t value, yaml_.Integer(seed, 0, UINT64_MAX));
      plan.spec.set_seed(value);
    }
    if (const YamlAt physics = YamlReader::Child(top, "physics"); YamlReader::Has(physics)) {
      RETURN_IF_ERROR(yaml_.FillMessage(physics, plan.spec.mutable_physics()));
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

  // A mesh file in its unit, or an uploaded mesh (metres), at item's keys mesh, unit and mesh_id.
  Status ParseMeshSource(const YamlAt& item, BinPlanPart* part) const {
    const YamlAt mesh = YamlReader::Child(item, "mesh");
    const YamlAt mesh_id = YamlReader::Child(item, "mesh_id");
    const YamlAt unit = YamlReader::Child(item, "unit");
    if (YamlReader::Has(mesh) == YamlReader::Has(mesh_id)) {
      return yaml_.Error(item, "give either mesh (a file) or mesh_id (an uploaded mesh)");
    }
    if (YamlReader::Has(mesh)) {
      ASSIGN_OR_RETURN(part->mesh, ReadPlanPath(yaml_, mesh, base_dir_));
      if (!YamlReader::Has(unit)) return yaml_.Error(unit, "required: the unit the mesh is written in (m, cm, mm, in, ft)");
      ASSIGN_OR_RETURN(const std::string text, yaml_.String(unit));
      const auto parsed = ParseUnit(text);
      if (!parsed.ok()) return yaml_.Error(unit, std::string(parsed.status().text()));
      part->unit = *parsed;
    } else {
      if (YamlReader::Has(unit)) return yaml_.Error(unit, "an uploaded mesh is in metres already; use scale");
      ASSIGN_OR_RETURN(part->mesh_id, yaml_.String(mesh_id));
    }
    return Status::Ok();
  }

  Status ParseBin(const YamlAt& at, BinPlan* plan) const {
    if (!YamlReader::Has(at)) {
      return yaml_.Error(at, "required: {inner_size: [x, y, z], wall_thickness, pose} or {mesh, unit, scale, pose}");
    }
    if (at.node.IsMap() && (at.node["mesh"] || at.node["mesh_id"])) return ParseBinMesh(at, plan);
    v1::BinBox* bin = plan->spec.mutable_bin();
    RETURN_IF_ERROR(yaml_.ExpectMap(at, {"inner_size", "wall_thickness", "pose"}));
    const YamlAt size = YamlReader::Child(at, "inner_size");
    if (!YamlReader::Has(size)) return yaml_.Error(size, "required: [length, width, depth] in metres");
    ASSIGN_OR_RETURN(const Eigen::Vector3d inner, yaml_.Vector3(size));
    *bin->mutable_inner_size() = ToProto(inner);
    if (const YamlAt wall = YamlReader::Child(at, "wall_thickness"); YamlReader::Has(wall)) {
      ASSIGN_OR_RETURN(const double value, yaml_.Number(wall));
      if (!(value > 0)) return yaml_.Error(wall, "must be positive (metres)");
      bin->set_wall_thickness(value);
    }
    if (const YamlAt pose = YamlReader::Child(at, "pose"); YamlReader::Has(pose)) {
      ASSIGN_OR_RETURN(*bin->mutable_pose(), ReadPlanPose(yaml_, pose));
    }
    return Status::Ok();
  }

  Status ParseBinMesh(const YamlAt& at, BinPlan* plan) const {
    RETURN_IF_ERROR(yaml_.ExpectMap(at, {"mesh", "mesh_id", "unit", "scale", "pose"}));
    BinPlanPart source;
    RETURN_IF_ERROR(ParseMeshSource(at, &source));
    v1::BinMesh* bin = plan->spec.mutable_bin_mesh();
    if (const YamlAt scale = YamlReader::Child(at, "scale"); YamlReader::Has(scale)) {
      ASSIGN_OR_RETURN(const double value, yaml_.Number(scale));
      if (!(value > 0)) return yaml_.Error(scale, "must be positive");
      bin->set_scale(value);
    }
    if (const YamlAt pose = YamlReader::Child(at, "pose"); YamlReader::Has(pose)) {
      ASSIGN_OR_RETURN(*bin->mutable_pose(), ReadPlanPose(yaml_, pose));
    }
    plan->bin_mesh = std::move(source);
    return Status::Ok();
  }

  Status ParseParts(const YamlAt& at, BinPlan* plan) const {
    if (!YamlReader::Has(at)) return yaml_.Error(at, "required: a list of {mesh, unit, count, ...}");
    RETURN_IF_ERROR(yaml_.ExpectSequence(at, 1));
    for (size_t i = 0; i < at.node.size(); ++i) {
      const YamlAt item = YamlReader::Item(at, i);
      RETURN_IF_ERROR(yaml_.ExpectMap(item, {"mesh", "mesh_id", "unit", "count", "scale", "name", "mass_kg",
                                             "density_kg_per_m3", "collision"}));
      BinPlanPart part;
      v1::BinPart* spec = plan->spec.add_parts();
      RETURN_IF_ERROR(ParseMeshSource(item, &part));
      if (!part.mesh.empty()) spec->set_name(part.mesh.stem().string());
      const YamlAt count = YamlReader::Child(item, "count");
      if (!YamlReader::Has(count)) return yaml_.Error(count, "required: how many of this part");
      ASSIGN_OR_RETURN(const uint64_t n, yaml_.Integer(count, 1, kMaxCount));
      spec->set_count(static_cast<uint32_t>(n));
      if (const YamlAt scale = YamlReader::Child(item, "scale"); YamlReader::Has(scale)) {
        ASSIGN_OR_RETURN(const double value, yaml_.Number(scale));
        if (!(value > 0)) return yaml_.Error(scale, "must be positive");
        spec->set_scale(value);
      }
      if (const YamlAt name = YamlReader::Child(item, "name"); YamlReader::Has(name)) {
        ASSIGN_OR_RETURN(*spec->mutable_name(), yaml_.String(name));
      }
      for (const char* key : {"mass_kg", "density_kg_per_m3"}) {
        if (const YamlAt value_at = YamlReader::Child(item, key); YamlReader::Has(value_at)) {
          ASSIGN_OR_RETURN(const double value, yaml_.Number(value_at));
          if (!(value > 0)) return yaml_.Error(value_at, "must be positive");
          std::string(key) == "mass_kg" ? spec->set_mass_kg(value) : spec->set_density_kg_per_m3(value);
        }
      }
      if (const YamlAt collision = YamlReader::Child(item, "collision"); YamlReader::Has(collision)) {
        ASSIGN_OR_RETURN(const std::string text, yaml_.String(collision));
        if (text == "convex_hull") {
          spec->set_collision(v1::PART_COLLISION_CONVEX_HULL);
        } else if (text == "convex_decomposition") {
          spec->set_collision(v1::PART_COLLISION_CONVEX_DECOMPOSITION);
        } else {
          return yaml_.Error(collision,
                             "unknown collision shape '" + text + "' (convex_hull or convex_decomposition)");
        }
      }
      plan->parts.push_back(std::move(part));
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
