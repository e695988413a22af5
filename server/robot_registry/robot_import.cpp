#include "robot_registry/robot_import.h"

#include <urdf_model/model.h>

#include "robot/reach.h"
#include "robot/urdf_chain.h"
#include "robot_registry/bundle_codec.h"

namespace vscan::robot_registry {
namespace {

store::JointKind KindOf(robot::JointType type) {
  switch (type) {
    case robot::JointType::kRevolute: return store::JointKind::kRevolute;
    case robot::JointType::kContinuous: return store::JointKind::kContinuous;
    case robot::JointType::kPrismatic: return store::JointKind::kPrismatic;
    case robot::JointType::kFixed: return store::JointKind::kFixed;
  }
  return store::JointKind::kFixed;
}

// The engine names header values by their bare names; the request carries them in its header.
Status InHeader(const Status& status) {
  for (const char* field : {"urdf_path", "base_link", "tip_link"}) {
    if (status.field() == field) {
      // An unknown link is a bad argument of this request, not a missing resource.
      const StatusCode code = status.code() == StatusCode::kNotFound ? StatusCode::kInvalidArgument : status.code();
      return status.WithFieldPrefix("header").WithCode(code);
    }
  }
  return status;
}

std::vector<store::JointRecord> JointRecords(const robot::KinematicChain& chain, const urdf::ModelInterface& model) {
  std::vector<store::JointRecord> joints;
  for (const robot::ChainJoint& j : chain.joints()) {
    store::JointRecord record{j.name, KindOf(j.type), j.lower, j.upper, 0.0};
    if (const auto joint = model.getJoint(j.name); joint != nullptr && joint->limits != nullptr) {
      record.max_velocity = joint->limits->velocity;
    }
    joints.push_back(std::move(record));
  }
  return joints;
}

}  // namespace

StatusOr<ImportedRobot> ImportRobot(RobotUpload upload, const robot::BundleLimits& limits) {
  if (upload.urdf_path.empty()) return InvalidArgument("header.urdf_path: required (the URDF's path in the bundle)");
  const size_t file_count = upload.files.size();
  auto bundle = robot::LoadUrdfBundle(upload.urdf_path, std::move(upload.files), limits);
  if (!bundle.ok()) return InHeader(bundle.status());

  robot::ChainSpec spec{upload.base_link, upload.tip_link, upload.tip_from_tool};
  auto chain = robot::BuildChain(*bundle->model, spec);
  if (!chain.ok()) return InHeader(chain.status());

  ImportedRobot out;
  store::RobotRecord& r = out.record;
  r.name = upload.name.empty() ? bundle->model->getName() : upload.name;
  r.urdf_path = bundle->urdf_path;
  r.base_link = chain->base_link();
  r.tip_link = chain->tip_link();
  r.tool_offset = upload.tip_from_tool.matrix();
  r.file_count = static_cast<uint32_t>(file_count);
  for (const auto& [path, bytes] : bundle->files) r.bundle_bytes += bytes.size();
  r.joints = JointRecords(*chain, *bundle->model);
  r.reach = robot::ReachUpperBound(*chain);
  r.warnings = bundle->warnings;
  out.bundle_blob = EncodeBundle(bundle->files);
  out.chain = std::make_shared<const robot::KinematicChain>(std::move(chain).value());
  return out;
}

StatusOr<std::shared_ptr<const robot::KinematicChain>> LoadStoredChain(const store::RobotRecord& record,
                                                                       std::vector<robot::BundleFile> files) {
  // The bundle passed these checks at upload; limits here only guard against a damaged store.
  robot::BundleLimits limits;
  limits.max_total_bytes = ~uint64_t{0};
  limits.max_files = ~uint32_t{0};
  auto bundle = robot::LoadUrdfBundle(record.urdf_path, std::move(files), limits);
  if (!bundle.ok()) return DataLoss("robot '" + record.robot_id + "': stored bundle: " + bundle.status().message());
  Pose3 tool = Pose3::Identity();
  tool.matrix() = record.tool_offset;
  auto chain = robot::BuildChain(*bundle->model, {record.base_link, record.tip_link, tool});
  if (!chain.ok()) return DataLoss("robot '" + record.robot_id + "': stored bundle: " + chain.status().message());
  return std::make_shared<const robot::KinematicChain>(std::move(chain).value());
}

}  // namespace vscan::robot_registry
