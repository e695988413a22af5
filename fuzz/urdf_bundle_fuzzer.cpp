// libFuzzer target for a robot upload: a URDF bundle through LoadUrdfBundle, then the chain
// BuildChain extracts and its kinematics. The input is the URDF text, optionally followed by more
// bundle files, each introduced by a line "\n==> <path>\n"; the URDF is "robot.urdf". An accepted
// bundle's chain must keep every pose finite and the tool within ReachUpperBound of the first
// joint, the bound vscand checks mounts and viewpoints against.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "robot/forward_kinematics.h"
#include "robot/reach.h"
#include "robot/urdf_bundle.h"
#include "robot/urdf_chain.h"

namespace {

using vscan::StatusCode;
using vscan::robot::BundleFile;
using vscan::robot::KinematicChain;

constexpr std::string_view kUrdfPath = "robot.urdf";
constexpr std::string_view kSeparator = "\n==> ";

void Check(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "urdf_bundle_fuzzer: %s\n", what);
  std::abort();
}

std::vector<BundleFile> SplitBundle(std::string_view input) {
  std::vector<BundleFile> files;
  size_t end = input.find(kSeparator);
  files.push_back({std::string(kUrdfPath), std::string(input.substr(0, end))});
  while (end != std::string_view::npos) {
    input.remove_prefix(end + kSeparator.size());
    const size_t line_end = input.find('\n');
    std::string path(input.substr(0, line_end));
    input.remove_prefix(line_end == std::string_view::npos ? input.size() : line_end + 1);
    end = input.find(kSeparator);
    files.push_back({std::move(path), std::string(input.substr(0, end))});
  }
  return files;
}

// A refusal the client can act on; INTERNAL or UNKNOWN would mean the parser lost its way.
void CheckRefusal(StatusCode code, const char* stage) {
  if (code == StatusCode::kInvalidArgument || code == StatusCode::kNotFound ||
      code == StatusCode::kResourceExhausted) {
    return;
  }
  std::fprintf(stderr, "urdf_bundle_fuzzer: %s refused with code %s\n", stage, vscan::StatusCodeName(code));
  std::abort();
}

void CheckPoseWithinReach(const KinematicChain& chain, const Eigen::VectorXd& q) {
  if (!vscan::robot::ValidateJointPositions(chain, q).ok()) return;
  const auto tool = vscan::robot::ForwardKinematics(chain, q);
  Check(tool.ok(), "forward kinematics failed on valid joint positions");
  Check(tool->matrix().allFinite(), "forward kinematics gave a non-finite pose");
  const double reach = vscan::robot::ReachUpperBound(chain);
  const double distance = (tool->translation() - vscan::robot::FirstJointOrigin(chain)).norm();
  Check(distance <= reach * (1 + 1e-9) + 1e-9, "the tool reached beyond ReachUpperBound");
  const auto links = vscan::robot::ChainLinkPoses(chain, q);
  Check(links.ok(), "link poses failed on valid joint positions");
  for (const auto& link : *links) Check(link.base_from_link.matrix().allFinite(), "non-finite link pose");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  vscan::robot::BundleLimits limits;
  limits.max_total_bytes = 1 << 20;
  limits.max_files = 16;
  const auto bundle = vscan::robot::LoadUrdfBundle(kUrdfPath, SplitBundle(input), limits);
  if (!bundle.ok()) {
    CheckRefusal(bundle.status().code(), "LoadUrdfBundle");
    return 0;
  }
  Check(bundle->model != nullptr, "accepted bundle without a model");
  for (const auto& mesh : bundle->meshes) {
    Check(mesh.bundle_path.empty() || bundle->files.count(mesh.bundle_path) == 1,
          "mesh reference resolved to a file the bundle lacks");
    Check(mesh.scale.allFinite(), "mesh scale not finite");
  }
  const auto chain = vscan::robot::BuildChain(*bundle->model, {});
  if (!chain.ok()) {
    CheckRefusal(chain.status().code(), "BuildChain");
    return 0;
  }
  Check(chain->dof() <= vscan::robot::kMaxChainJoints, "chain beyond kMaxChainJoints");
  Check(std::isfinite(vscan::robot::ReachUpperBound(*chain)), "ReachUpperBound not finite");
  Eigen::VectorXd lower(chain->dof()), middle(chain->dof()), upper(chain->dof());
  for (int i = 0; i < chain->dof(); ++i) {
    const auto& joint = chain->joints()[static_cast<size_t>(i)];
    lower[i] = joint.sample_lower;
    upper[i] = joint.sample_upper;
    middle[i] = 0.5 * (joint.sample_lower + joint.sample_upper);
  }
  for (const Eigen::VectorXd& q : {lower, middle, upper}) CheckPoseWithinReach(*chain, q);
  return 0;
}
