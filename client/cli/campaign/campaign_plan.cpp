#include "campaign/campaign_plan.h"

#include <functional>
#include <tuple>

#include "campaign/yaml_messages.h"
#include "campaign/plan_values.h"
#include "session/args.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

// Drops the "--option" an args.h message names, so that the plan's key path can stand there.
std::string Reason(const Status& status) {
  return status.field().starts_with("--") ? std::string(status.text()) : status.message();
}

class PlanParser {
 public:
  PlanParser(const std::string& source, std::filesystem::path base_dir)
      : yaml_(source), base_dir_(std::move(base_dir)), default_name_(std::filesystem::path(source).stem().string()) {}

  StatusOr<CampaignPlan> Parse(const YAML::Node& root) {
    const YamlAt top{root, "", root.Mark()};
    if (!root.IsMap())
      return yaml_.Error(top, "a plan is a mapping with keys name, scene, robot, sensor, viewpoints, ...");
    RETURN_IF_ERROR(yaml_.ExpectMap(top, {"name", "scene", "scene_id", "robot", "mount_id", "sensor", "noise",
                                          "backend", "fields", "frame", "viewpoints", "rotations", "rotation_step_deg",
                                          "start_angle_deg", "seed", "apply_encoder_noise", "reject_collisions",
                                          "align", "reconstruct", "evaluate", "alignment", "reconstruction",
                                          "evaluation", "returned_light"}));
    CampaignPlan plan;
    plan.name = default_name_;
    if (const YamlAt at = YamlReader::Child(top, "name"); YamlReader::Has(at)) {
      ASSIGN_OR_RETURN(plan.name, yaml_.String(at));
    }
    plan.spec.set_name(plan.name);
    RETURN_IF_ERROR(ParseSceneChoice(top, &plan));
    RETURN_IF_ERROR(ParseRobotChoice(top, &plan));
    RETURN_IF_ERROR(ParseSensor(top, &plan.spec));
    RETURN_IF_ERROR(ParseViewpoints(YamlReader::Child(top, "viewpoints"), &plan.spec));
    RETURN_IF_ERROR(ParseSchedule(top, &plan.spec));
    RETURN_IF_ERROR(ParseModel(top, &plan.spec));
    return plan;
  }

 private:
  // Exactly one of `key` (something to build) and `id_key` (an existing id).
  Status OneOf(const YamlAt& top, const char* key, const char* id_key) const {
    const bool build = YamlReader::Has(YamlReader::Child(top, key));
    const bool existing = YamlReader::Has(YamlReader::Child(top, id_key));
    if (build && existing) {
      return yaml_.Error(YamlReader::Child(top, id_key),
                         std::string("give either ") + key + " or " + id_key + ", not both");
    }
    if (!build && !existing) {
      return yaml_.Error(top.mark, key, std::string("required (or ") + id_key + " to use an existing one)");
    }
    return Status::Ok();
  }

  Status ParseSceneChoice(const YamlAt& top, CampaignPlan* plan) const {
    RETURN_IF_ERROR(OneOf(top, "scene", "scene_id"));
    if (const YamlAt id = YamlReader::Child(top, "scene_id"); YamlReader::Has(id)) {
      ASSIGN_OR_RETURN(plan->scene_id, yaml_.String(id));
      return Status::Ok();
    }
    ASSIGN_OR_RETURN(plan->scene, ParseScene(YamlReader::Child(top, "scene"), plan->name));
    return Status::Ok();
  }

  StatusOr<PlanScene> ParseScene(const YamlAt& at, const std::string& plan_name) const {
    RETURN_IF_ERROR(yaml_.ExpectMap(at, {"name", "objects", "table"}));
    PlanScene scene;
    scene.name = plan_name;
    if (const YamlAt name = YamlReader::Child(at, "name"); YamlReader::Has(name)) {
      ASSIGN_OR_RETURN(scene.name, yaml_.String(name));
    }
    const YamlAt objects = YamlReader::Child(at, "objects");
    if (!YamlReader::Has(objects)) return yaml_.Error(objects, "required: a list of {mesh, unit, ...}");
    RETURN_IF_ERROR(yaml_.ExpectSequence(objects, 1));
    for (size_t i = 0; i < objects.node.size(); ++i) {
      ASSIGN_OR_RETURN(PlanObject object, ParseObject(YamlReader::Item(objects, i)));
      scene.objects.push_back(std::move(object));
    }
    if (const YamlAt table = YamlReader::Child(at, "table"); YamlReader::Has(table)) {
      ASSIGN_OR_RETURN(scene.table, ParseTable(table));
    }
    return scene;
  }

  StatusOr<PlanObject> ParseObject(const YamlAt& at) const {
    RETURN_IF_ERROR(yaml_.ExpectMap(at, {"mesh", "unit", "scale", "label", "pose", "on_table", "material"}));
    PlanObject object;
    ASSIGN_OR_RETURN(object.mesh, ExistingPath(YamlReader::Child(at, "mesh")));
    const YamlAt unit_at = YamlReader::Child(at, "unit");
    if (!YamlReader::Has(unit_at))
      return yaml_.Error(unit_at, "required: the unit the mesh is written in (m, cm, mm, in, ft)");
    ASSIGN_OR_RETURN(const std::string unit_text, yaml_.String(unit_at));
    const auto unit = ParseUnit(unit_text);
    if (!unit.ok()) return yaml_.Error(unit_at, Reason(unit.status()));
    object.unit = *unit;
    if (const YamlAt scale = YamlReader::Child(at, "scale"); YamlReader::Has(scale)) {
      ASSIGN_OR_RETURN(object.scale, yaml_.Number(scale));
      if (!(object.scale > 0)) return yaml_.Error(scale, "must be positive");
    }
    if (const YamlAt label = YamlReader::Child(at, "label"); YamlReader::Has(label)) {
      ASSIGN_OR_RETURN(object.label, yaml_.String(label));
    }
    if (const YamlAt pose = YamlReader::Child(at, "pose"); YamlReader::Has(pose)) {
      ASSIGN_OR_RETURN(object.pose, ParsePose(pose));
    }
    if (const YamlAt on_table = YamlReader::Child(at, "on_table"); YamlReader::Has(on_table)) {
      ASSIGN_OR_RETURN(object.on_table, yaml_.Bool(on_table));
    }
    if (const YamlAt material = YamlReader::Child(at, "material"); YamlReader::Has(material)) {
      if (plan::IsMaterialChoice(material)) {
        return yaml_.Error(material, "a campaign's object has one material; choose is for dataset plans");
      }
      ASSIGN_OR_RETURN(const plan::MaterialPlan read, plan::ReadMaterial(yaml_, material));
      object.material = MaterialMessage(read);
    }
    return object;
  }

  StatusOr<v1::RotaryTable> ParseTable(const YamlAt& at) const {
    RETURN_IF_ERROR(yaml_.ExpectMap(at, {"centre", "center", "axis", "angle_deg", "angle", "enabled"}));
    v1::RotaryTable table;
    table.set_enabled(true);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    for (const char* key : {"centre", "center"}) {
      if (const YamlAt c = YamlReader::Child(at, key); YamlReader::Has(c)) {
        ASSIGN_OR_RETURN(centre, yaml_.Vector3(c));
      }
    }
    if (const YamlAt a = YamlReader::Child(at, "axis"); YamlReader::Has(a)) {
      ASSIGN_OR_RETURN(axis, yaml_.Vector3(a));
      if (axis.norm() == 0) return yaml_.Error(a, "must not be the zero vector");
    }
    for (const char* key : {"angle_deg", "angle"}) {
      if (const YamlAt angle = YamlReader::Child(at, key); YamlReader::Has(angle)) {
        ASSIGN_OR_RETURN(const double deg, yaml_.Number(angle));
        table.set_angle_deg(deg);
      }
    }
    if (const YamlAt enabled = YamlReader::Child(at, "enabled"); YamlReader::Has(enabled)) {
      ASSIGN_OR_RETURN(const bool on, yaml_.Bool(enabled));
      table.set_enabled(on);
    }
    *table.mutable_centre() = ToProto(centre);
    *table.mutable_axis() = ToProto(axis.normalized());
    return table;
  }

  Status ParseRobotChoice(const YamlAt& top, CampaignPlan* plan) const {
    RETURN_IF_ERROR(OneOf(top, "robot", "mount_id"));
    if (const YamlAt id = YamlReader::Child(top, "mount_id"); YamlReader::Has(id)) {
      if (plan->scene) return yaml_.Error(id, "an existing mount belongs to an existing scene: use scene_id too");
      ASSIGN_OR_RETURN(plan->mount_id, yaml_.String(id));
      return Status::Ok();
    }
    ASSIGN_OR_RETURN(plan->robot, ParseRobot(YamlReader::Child(top, "robot")));
    return Status::Ok();
  }

  StatusOr<PlanRobot> ParseRobot(const YamlAt& at) const {
    RETURN_IF_ERROR(yaml_.ExpectMap(
        at, {"bundle", "urdf", "base_link", "tip_link", "base_pose", "tool_offset", "encoder_sigma", "links_visible"}));
    PlanRobot robot;
    ASSIGN_OR_RETURN(robot.bundle, ExistingPath(YamlReader::Child(at, "bundle")));
    const std::pair<const char*, std::string*> names[] = {
        {"urdf", &robot.urdf}, {"base_link", &robot.base_link}, {"tip_link", &robot.tip_link}};
    for (const auto& [key, out] : names) {
      if (const YamlAt v = YamlReader::Child(at, key); YamlReader::Has(v)) {
        ASSIGN_OR_RETURN(*out, yaml_.String(v));
      }
    }
    if (!robot.urdf.empty() && std::filesystem::is_directory(robot.bundle) &&
        !std::filesystem::exists(robot.bundle / robot.urdf)) {
      return yaml_.Error(YamlReader::Child(at, "urdf"), "no file '" + robot.urdf + "' in " + robot.bundle.string());
    }
    if (const YamlAt base = YamlReader::Child(at, "base_pose"); YamlReader::Has(base)) {
      ASSIGN_OR_RETURN(*robot.mount.mutable_base_pose(), ParsePose(base));
    }
    if (const YamlAt tool = YamlReader::Child(at, "tool_offset"); YamlReader::Has(tool)) {
      ASSIGN_OR_RETURN(*robot.mount.mutable_tool_offset(), ParsePose(tool));
    }
    if (const YamlAt sigma = YamlReader::Child(at, "encoder_sigma"); YamlReader::Has(sigma)) {
      ASSIGN_OR_RETURN(const auto values, yaml_.NumberOrList(sigma));
      for (const double s : values) {
        if (s < 0) return yaml_.Error(sigma, "must not be negative");
        robot.mount.add_encoder_sigma(s);
      }
    }
    if (const YamlAt visible = YamlReader::Child(at, "links_visible"); YamlReader::Has(visible)) {
      ASSIGN_OR_RETURN(const bool on, yaml_.Bool(visible));
      robot.mount.set_links_visible(on);
    }
    return robot;
  }

  StatusOr<v1::Pose> ParsePose(const YamlAt& at) const { return ReadPlanPose(yaml_, at); }
  StatusOr<Eigen::Vector3d> RequiredVector(const YamlAt& at) const { return vscan::cli::RequiredVector(yaml_, at); }

  Status ParseSensor(const YamlAt& top, v1::CampaignSpec* spec) const {
    const YamlAt sensor = YamlReader::Child(top, "sensor");
    if (!YamlReader::Has(sensor)) {
      return yaml_.Error(sensor, "required: {preset: NAME} or {pinhole: {width, height, horizontal_fov_deg, ...}}");
    }
    RETURN_IF_ERROR(FillMessage(yaml_, sensor, spec->mutable_sensor()));
    if (spec->sensor().kind_case() == v1::SensorSpec::KIND_NOT_SET) {
      return yaml_.Error(sensor, "give preset, pinhole or structured_light");
    }
    if (const YamlAt noise = YamlReader::Child(top, "noise"); YamlReader::Has(noise)) {
      RETURN_IF_ERROR(FillMessage(yaml_, noise, spec->mutable_noise()));
    }
    if (const YamlAt backend = YamlReader::Child(top, "backend"); YamlReader::Has(backend)) {
      ASSIGN_OR_RETURN(const std::string text, yaml_.String(backend));
      const auto parsed = ParseBackend(text);
      if (!parsed.ok()) return yaml_.Error(backend, Reason(parsed.status()));
      spec->set_backend(*parsed);
    } else {
      spec->set_backend(v1::SCAN_BACKEND_RAYCAST);
    }
    if (const YamlAt fields = YamlReader::Child(top, "fields"); YamlReader::Has(fields)) {
      ASSIGN_OR_RETURN(const std::string text, yaml_.StringOrList(fields));
      const auto parsed = ParseFields(text);
      if (!parsed.ok()) return yaml_.Error(fields, Reason(parsed.status()));
      for (const auto f : *parsed) spec->add_fields(f);
    }
    spec->set_frame(v1::FRAME_WORLD);
    if (const YamlAt frame = YamlReader::Child(top, "frame"); YamlReader::Has(frame)) {
      ASSIGN_OR_RETURN(const std::string text, yaml_.String(frame));
      const auto parsed = ParseFrame(text);
      if (!parsed.ok()) return yaml_.Error(frame, Reason(parsed.status()));
      spec->set_frame(*parsed);
    }
    if (const YamlAt light = YamlReader::Child(top, "returned_light"); YamlReader::Has(light)) {
      RETURN_IF_ERROR(FillMessage(yaml_, light, spec->mutable_returned_light()));
    }
    return Status::Ok();
  }

  Status ParseViewpoints(const YamlAt& at, v1::CampaignSpec* spec) const {
    if (!YamlReader::Has(at)) return yaml_.Error(at, "required: a list of {position, target, up?}");
    RETURN_IF_ERROR(yaml_.ExpectSequence(at, 1));
    for (size_t i = 0; i < at.node.size(); ++i) {
      const YamlAt item = YamlReader::Item(at, i);
      RETURN_IF_ERROR(yaml_.ExpectMap(item, {"position", "target", "up"}));
      ASSIGN_OR_RETURN(const Eigen::Vector3d position, RequiredVector(YamlReader::Child(item, "position")));
      ASSIGN_OR_RETURN(const Eigen::Vector3d target, RequiredVector(YamlReader::Child(item, "target")));
      v1::Viewpoint* viewpoint = spec->add_viewpoints();
      *viewpoint->mutable_position() = ToProto(position);
      *viewpoint->mutable_target() = ToProto(target);
      if (const YamlAt u = YamlReader::Child(item, "up"); YamlReader::Has(u)) {
        ASSIGN_OR_RETURN(const Eigen::Vector3d up, yaml_.Vector3(u));
        *viewpoint->mutable_up() = ToProto(up);
      }
    }
    return Status::Ok();
  }

  Status ParseSchedule(const YamlAt& top, v1::CampaignSpec* spec) const {
    uint64_t rotations = 1;
    if (const YamlAt r = YamlReader::Child(top, "rotations"); YamlReader::Has(r)) {
      // The upper bound is the server's (checked with validate_only before anything is uploaded).
      ASSIGN_OR_RETURN(rotations, yaml_.Integer(r, 1, UINT32_MAX));
    }
    spec->set_rotations(static_cast<uint32_t>(rotations));
    // A full turn split evenly unless the step is given.
    spec->set_rotation_step_deg(360.0 / static_cast<double>(rotations));
    if (const YamlAt step = YamlReader::Child(top, "rotation_step_deg"); YamlReader::Has(step)) {
      ASSIGN_OR_RETURN(const double deg, yaml_.Number(step));
      spec->set_rotation_step_deg(deg);
    }
    if (const YamlAt start = YamlReader::Child(top, "start_angle_deg"); YamlReader::Has(start)) {
      ASSIGN_OR_RETURN(const double deg, yaml_.Number(start));
      spec->set_start_angle_deg(deg);
    }
    if (const YamlAt seed = YamlReader::Child(top, "seed"); YamlReader::Has(seed)) {
      ASSIGN_OR_RETURN(const uint64_t v, yaml_.Integer(seed, 0, UINT64_MAX));
      spec->set_seed(v);
    }
    if (const YamlAt noise = YamlReader::Child(top, "apply_encoder_noise"); YamlReader::Has(noise)) {
      ASSIGN_OR_RETURN(const bool on, yaml_.Bool(noise));
      spec->set_apply_encoder_noise(on);
    }
    if (const YamlAt reject = YamlReader::Child(top, "reject_collisions"); YamlReader::Has(reject)) {
      ASSIGN_OR_RETURN(const bool on, yaml_.Bool(reject));
      spec->set_reject_collisions(on);
    }
    return Status::Ok();
  }

  // align, reconstruct, evaluate and their option blocks; a block needs the part it tunes.
  Status ParseModel(const YamlAt& top, v1::CampaignSpec* spec) const {
    const std::pair<const char*, void (v1::CampaignSpec::*)(bool)> parts[] = {
        {"align", &v1::CampaignSpec::set_align},
        {"reconstruct", &v1::CampaignSpec::set_reconstruct},
        {"evaluate", &v1::CampaignSpec::set_evaluate}};
    for (const auto& [key, set] : parts) {
      if (const YamlAt at = YamlReader::Child(top, key); YamlReader::Has(at)) {
        ASSIGN_OR_RETURN(const bool on, yaml_.Bool(at));
        (spec->*set)(on);
      }
    }
    const bool aligns = spec->align() || spec->reconstruct() || spec->evaluate();
    const std::tuple<const char*, bool, const char*, std::function<google::protobuf::Message*()>> blocks[] = {
        {"alignment", aligns, "align, reconstruct or evaluate", [spec] { return spec->mutable_alignment(); }},
        {"reconstruction", spec->reconstruct(), "reconstruct", [spec] { return spec->mutable_reconstruction(); }},
        {"evaluation", spec->evaluate(), "evaluate", [spec] { return spec->mutable_evaluation(); }}};
    for (const auto& [key, wanted, needs, message] : blocks) {
      const YamlAt at = YamlReader::Child(top, key);
      if (!YamlReader::Has(at)) continue;
      if (!wanted) {
        return yaml_.Error(KeyMark(top, key), key,
                           std::string("tunes a part that does not run: set ") + needs + ": true");
      }
      RETURN_IF_ERROR(FillMessage(yaml_, at, message()));
    }
    return Status::Ok();
  }

  // Where key stands in the map (a block mapping's own mark is its first key's line).
  static YAML::Mark KeyMark(const YamlAt& map, const std::string& key) {
    for (const auto& entry : map.node) {
      if (entry.first.Scalar() == key) return entry.first.Mark();
    }
    return map.mark;
  }

  // A path relative to the plan's directory that must exist.
  StatusOr<std::filesystem::path> ExistingPath(const YamlAt& at) const {
    return ReadPlanPath(yaml_, at, base_dir_);
  }

  YamlReader yaml_;
  std::filesystem::path base_dir_;
  std::string default_name_;
};

}  // namespace

StatusOr<CampaignPlan> ParseCampaignPlan(const std::string& yaml, const std::string& source,
                                         const std::filesystem::path& base_dir) {
  return ParsePlanDocument<CampaignPlan>(
      yaml, source, [&](const YAML::Node& root) { return PlanParser(source, base_dir).Parse(root); });
}

StatusOr<CampaignPlan> LoadCampaignPlan(const std::string& path) {
  ASSIGN_OR_RETURN(const std::string text, ReadPlanFile(path));
  return ParseCampaignPlan(text, path, std::filesystem::path(path).parent_path());
}

}  // namespace vscan::cli
