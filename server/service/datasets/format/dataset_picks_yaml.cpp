#include "service/datasets/format/dataset_picks_yaml.h"

#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>

#include <Eigen/Geometry>

#include "grasping/public_field_names.h"

namespace vscan::service::dataset {
namespace {

using plan::YamlAt;
using plan::YamlReader;

// An engine check's error at the key it names, within the section at.
Status AtPlanKey(const YamlReader& yaml, const YamlAt& at, const Status& checked) {
  if (checked.ok()) return checked;
  const std::string field(grasping::PublicFieldName(checked.field()));
  // The line of the key when the plan wrote it, else the section's.
  YamlAt key = at;
  size_t from = 0;
  while (from <= field.size()) {
    const size_t dot = std::min(field.find('.', from), field.size());
    const YamlAt child = YamlReader::Child(key, field.substr(from, dot - from));
    if (!YamlReader::Has(child)) break;
    key = child;
    from = dot + 1;
  }
  return yaml.Error(key.node.Mark().line >= 0 ? key.node.Mark() : at.node.Mark(), at.path + "." + field,
                    std::string(checked.text()));
}

template <typename T>
Status ReadNumber(const YamlReader& yaml, const YamlAt& map, const char* key, T& out) {
  const YamlAt at = YamlReader::Child(map, key);
  if (!YamlReader::Has(at)) return Status::Ok();
  ASSIGN_OR_RETURN(const double value, yaml.Number(at));
  out = static_cast<T>(value);
  return Status::Ok();
}

Status ReadCount(const YamlReader& yaml, const YamlAt& map, const char* key, uint64_t max, size_t& out) {
  const YamlAt at = YamlReader::Child(map, key);
  if (!YamlReader::Has(at)) return Status::Ok();
  ASSIGN_OR_RETURN(const uint64_t value, yaml.Integer(at, 0, max));
  out = static_cast<size_t>(value);
  return Status::Ok();
}

Eigen::Matrix3d RotationFromRpyDegrees(const std::vector<double>& rpy) {
  const double to_rad = std::numbers::pi / 180.0;
  return (Eigen::AngleAxisd(rpy[2] * to_rad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy[1] * to_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy[0] * to_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// {xyz: [x, y, z], rpy_deg: [roll, pitch, yaw]} or {xyz, quat: [w, x, y, z]}, metres; the
// rotation about fixed x, then y, then z, as campaign and bin plans read rpy_deg.
StatusOr<Pose3> ReadPose(const YamlReader& yaml, const YamlAt& at) {
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"xyz", "rpy_deg", "quat"}));
  const YamlAt xyz = YamlReader::Child(at, "xyz");
  const YamlAt rpy = YamlReader::Child(at, "rpy_deg");
  const YamlAt quat = YamlReader::Child(at, "quat");
  if (YamlReader::Has(rpy) && YamlReader::Has(quat)) return yaml.Error(quat, "give rpy_deg or quat, not both");
  Pose3 pose = Pose3::Identity();
  if (!YamlReader::Has(xyz)) return yaml.Error(at.node.Mark(), xyz.path, "required: [x, y, z] in metres");
  ASSIGN_OR_RETURN(pose.translation(), yaml.Vector3(xyz));
  // A robot kilometres from its bin reaches nothing and would only stretch the solver's numbers.
  if (pose.translation().norm() > 1000) return yaml.Error(xyz, "must be within 1000 m of the bin");
  if (YamlReader::Has(rpy)) {
    ASSIGN_OR_RETURN(const std::vector<double> v, yaml.Numbers(rpy, 3));
    for (const double angle : v) {
      if (std::abs(angle) > 3600) return yaml.Error(rpy, "angles must be within +-3600 degrees");
    }
    pose.linear() = RotationFromRpyDegrees(v);
  }
  if (YamlReader::Has(quat)) {
    ASSIGN_OR_RETURN(const std::vector<double> v, yaml.Numbers(quat, 4));
    const StatusOr<Pose3> q =
        PoseFromQuaternion(Eigen::Vector3d::Zero(), Eigen::Quaterniond(v[0], v[1], v[2], v[3]), "quat");
    if (!q.ok()) return yaml.Error(quat, "expected a unit quaternion w, x, y, z");
    pose.linear() = q->linear();
  }
  return pose;
}

StatusOr<grasping::Gripper> ReadGripper(const YamlReader& yaml, const YamlAt& at) {
  if (!YamlReader::Has(at)) return yaml.Error(at.mark, at.path, "required: {suction: {...}} or {jaws: {...}}");
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"suction", "jaws"}));
  const YamlAt suction = YamlReader::Child(at, "suction");
  const YamlAt jaws = YamlReader::Child(at, "jaws");
  if (YamlReader::Has(suction) == YamlReader::Has(jaws)) return yaml.Error(at, "give exactly one of suction and jaws");
  if (YamlReader::Has(suction)) {
    RETURN_IF_ERROR(yaml.ExpectMap(suction, {"diameter", "stroke", "max_tilt_deg", "min_flat_fraction"}));
    grasping::SuctionCup cup;
    RETURN_IF_ERROR(ReadNumber(yaml, suction, "diameter", cup.diameter_m));
    RETURN_IF_ERROR(ReadNumber(yaml, suction, "stroke", cup.stroke_m));
    RETURN_IF_ERROR(ReadNumber(yaml, suction, "max_tilt_deg", cup.max_tilt_deg));
    RETURN_IF_ERROR(ReadNumber(yaml, suction, "min_flat_fraction", cup.min_flat_fraction));
    return grasping::Gripper(cup);
  }
  RETURN_IF_ERROR(yaml.ExpectMap(jaws, {"min_opening", "max_opening", "finger_width", "finger_depth",
                                        "max_friction_angle_deg", "finger_length", "finger_thickness"}));
  grasping::ParallelJaws out;
  RETURN_IF_ERROR(ReadNumber(yaml, jaws, "min_opening", out.min_opening_m));
  RETURN_IF_ERROR(ReadNumber(yaml, jaws, "max_opening", out.max_opening_m));
  RETURN_IF_ERROR(ReadNumber(yaml, jaws, "finger_width", out.finger_width_m));
  RETURN_IF_ERROR(ReadNumber(yaml, jaws, "finger_depth", out.finger_depth_m));
  RETURN_IF_ERROR(ReadNumber(yaml, jaws, "max_friction_angle_deg", out.max_friction_angle_deg));
  RETURN_IF_ERROR(ReadNumber(yaml, jaws, "finger_length", out.finger_length_m));
  RETURN_IF_ERROR(ReadNumber(yaml, jaws, "finger_thickness", out.finger_thickness_m));
  return grasping::Gripper(out);
}

// The counts are read up to 2^53 so that a huge one reaches the engine's range check, which names it.
constexpr uint64_t kLargestCount = uint64_t{1} << 53;

Status ReadGraspOptions(const YamlReader& yaml, const YamlAt& at, grasping::GraspOptions& out) {
  if (!YamlReader::Has(at)) return Status::Ok();
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"max_grasps", "seed", "candidates", "surface_samples"}));
  RETURN_IF_ERROR(ReadCount(yaml, at, "max_grasps", kLargestCount, out.max_grasps));
  if (const YamlAt seed = YamlReader::Child(at, "seed"); YamlReader::Has(seed)) {
    ASSIGN_OR_RETURN(out.seed, yaml.Integer(seed, 0, UINT64_MAX));
  }
  RETURN_IF_ERROR(ReadCount(yaml, at, "candidates", kLargestCount, out.candidates));
  return ReadCount(yaml, at, "surface_samples", kLargestCount, out.surface_samples);
}

Status ReadPickOptions(const YamlReader& yaml, const YamlAt& at, DatasetPicks& out) {
  if (!YamlReader::Has(at)) return Status::Ok();
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"approach_distance", "max_approach_tilt_deg", "cover_distance",
                                      "max_reach_checks", "body_length", "ik_iterations"}));
  grasping::PickOptions& options = out.pick_options;
  RETURN_IF_ERROR(ReadNumber(yaml, at, "approach_distance", options.sweep.approach_m));
  RETURN_IF_ERROR(ReadNumber(yaml, at, "max_approach_tilt_deg", options.max_approach_tilt_deg));
  RETURN_IF_ERROR(ReadNumber(yaml, at, "cover_distance", options.cover_distance_m));
  RETURN_IF_ERROR(ReadCount(yaml, at, "max_reach_checks", kLargestCount, options.max_reach_checks));
  RETURN_IF_ERROR(ReadNumber(yaml, at, "body_length", options.sweep.body_length_m));
  if (const YamlAt iterations = YamlReader::Child(at, "ik_iterations"); YamlReader::Has(iterations)) {
    ASSIGN_OR_RETURN(const uint64_t value, yaml.Integer(iterations, kMinIkIterations, kMaxIkIterations));
    out.ik_iterations = static_cast<size_t>(value);
  }
  return Status::Ok();
}

}  // namespace

StatusOr<DatasetPicks> ReadDatasetPicks(const YamlReader& yaml, const YamlAt& at) {
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"robot_id", "base", "tool", "gripper", "grasp_options", "pick_options"}));
  DatasetPicks picks;
  // Unset, the body reaches from the tool centre point back to the flange (the robot's tool).
  picks.pick_options.sweep.body_length_m = 0;
  const YamlAt robot = YamlReader::Child(at, "robot_id");
  if (!YamlReader::Has(robot)) return yaml.Error(at.node.Mark(), robot.path, "required: a stored robot's id");
  ASSIGN_OR_RETURN(picks.robot_id, yaml.String(robot));
  const YamlAt base = YamlReader::Child(at, "base");
  if (!YamlReader::Has(base)) {
    return yaml.Error(at.node.Mark(), base.path, "required: where the robot's base stands, {xyz, rpy_deg}");
  }
  ASSIGN_OR_RETURN(picks.world_from_base, ReadPose(yaml, base));
  if (const YamlAt tool = YamlReader::Child(at, "tool"); YamlReader::Has(tool)) {
    ASSIGN_OR_RETURN(picks.flange_from_tool, ReadPose(yaml, tool));
  }
  const YamlAt gripper = YamlReader::Child(at, "gripper");
  ASSIGN_OR_RETURN(picks.gripper, ReadGripper(yaml, gripper));
  RETURN_IF_ERROR(AtPlanKey(yaml, at, grasping::ValidateGripper(picks.gripper)));
  RETURN_IF_ERROR(ReadGraspOptions(yaml, YamlReader::Child(at, "grasp_options"), picks.grasp_options));
  RETURN_IF_ERROR(AtPlanKey(yaml, at, grasping::ValidateGraspOptions(picks.grasp_options)));
  RETURN_IF_ERROR(ReadPickOptions(yaml, YamlReader::Child(at, "pick_options"), picks));
  picks.pick_options.seed = picks.grasp_options.seed;
  RETURN_IF_ERROR(AtPlanKey(yaml, at, grasping::ValidatePickOptions(picks.pick_options)));
  return picks;
}

}  // namespace vscan::service::dataset
