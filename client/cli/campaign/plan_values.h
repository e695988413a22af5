#pragma once
// Values every YAML plan reads the same way: poses and paths relative to the plan file.

#include <filesystem>

#include "campaign/yaml_messages.h"
#include "vscan/plan/bin_fill_plan.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/scene.pb.h"

namespace vscan::cli {

// {xyz, rpy_deg | quat} or {matrix} or {look_at: {eye, target, up}}, checked as the server checks
// poses.
StatusOr<v1::Pose> ReadPlanPose(const YamlReader& yaml, const YamlAt& at);

// [x, y, z] in metres, required.
StatusOr<Eigen::Vector3d> RequiredVector(const YamlReader& yaml, const YamlAt& at);

// A plan's material (plan::ReadMaterial) as the server takes it.
v1::Material MaterialMessage(const plan::MaterialPlan& material);

// A path relative to base_dir that must exist.
StatusOr<std::filesystem::path> ReadPlanPath(const YamlReader& yaml, const YamlAt& at,
                                             const std::filesystem::path& base_dir);

}  // namespace vscan::cli
