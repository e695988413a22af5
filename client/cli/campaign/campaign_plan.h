#pragma once
// A campaign plan: one YAML file that describes the scene, the robot, the sensor and the
// viewpoints of a scan campaign. Parsing needs no server; every error names the file, the line and
// the key path ("plan.yaml:14: viewpoints[2].target: expected 3 numbers").

#include <yaml-cpp/mark.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "vscan/common/status.h"
#include "vscan/v1/job.pb.h"
#include "vscan/v1/robot.pb.h"
#include "vscan/v1/scene.pb.h"

namespace vscan::cli {

struct PlanObject {
  // Resolved against the plan's directory.
  std::filesystem::path mesh;
  v1::LengthUnit unit = v1::LENGTH_UNIT_UNSPECIFIED;
  double scale = 1.0;
  std::string label;
  // parent_from_object; unset means identity.
  std::optional<v1::Pose> pose;
  bool on_table = false;
  // Overrides the mesh's material (plan::ReadMaterial); unset: matte-grey.
  std::optional<v1::Material> material;
};

struct PlanScene {
  std::string name;
  std::vector<PlanObject> objects;
  std::optional<v1::RotaryTable> table;
};

struct PlanRobot {
  // Bundle directory (or single URDF file), resolved against the plan's directory.
  std::filesystem::path bundle;
  // Path of the URDF inside the bundle; empty: the bundle's only .urdf.
  std::string urdf;
  std::string base_link;
  std::string tip_link;
  // Everything but scene_id and robot_id, which exist only once the plan runs.
  v1::MountRobotRequest mount;
};

struct CampaignPlan {
  std::string name;
  // Either a scene to build or an existing scene's id.
  std::optional<PlanScene> scene;
  std::string scene_id;
  // Either a robot to upload and mount or an existing mount's id.
  std::optional<PlanRobot> robot;
  std::string mount_id;
  // scene_id and mount_id are filled in when the plan runs.
  v1::CampaignSpec spec;
  // The plan's name in messages, and where each key path ("viewpoints[2].target"; "" the whole
  // plan) stands in it, so that errors found later still name the file and the line.
  std::string source;
  std::map<std::string, YAML::Mark> key_marks;
};

// source names the text in messages (usually the path as given); relative paths in the plan are
// resolved against base_dir. Malformed plans are INVALID_ARGUMENT.
StatusOr<CampaignPlan> ParseCampaignPlan(const std::string& yaml, const std::string& source,
                                         const std::filesystem::path& base_dir);
// Reads path (NOT_FOUND when it cannot be read) and parses it relative to its directory.
StatusOr<CampaignPlan> LoadCampaignPlan(const std::string& path);

}  // namespace vscan::cli
