// libFuzzer target for the request checks of server/api: the first byte picks the message and its
// encoding (byte % 8: campaign spec, bin fill spec, model spec, dataset spec, localize request,
// score poses request, forward kinematics request, inverse kinematics request; (byte / 8) % 2:
// protobuf text or binary), the
// rest is the message. Checks run against the small world of scan_fuzz_world.cpp; the ids "scene"
// and "panda" (or another name of ScanFuzzWorld::mounts) stand for its scene and mounts. A finding
// is an abort or sanitizer report, a refusal whose code is OK, INTERNAL or UNKNOWN, or an accepted
// request that breaks a bound the contract documents.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/stubs/logging.h>
#include <google/protobuf/text_format.h>

#include "api/bins/bin_fill_spec.h"
#include "api/campaign/campaign_spec.h"
#include "api/datasets/dataset_spec.h"
#include "api/localization/localization_request.h"
#include "api/model/model_spec.h"
#include "api/robot/ik_request.h"
#include "robot/forward_kinematics.h"
#include "robot_registry/arm_kinematics.h"
#include "scan_fuzz_world.h"
#include "service/robot/inverse_kinematics.h"
#include "store/job_catalogue.h"
#include "vscan/v1/robot.pb.h"

namespace {

using vscan::Status;
using vscan::StatusCode;
using vscan::fuzz::ScanFuzzWorld;
using vscan::fuzz::World;

constexpr int kKinds = 8;
// Solves run on each accepted request; a short budget keeps the rate of executions up.
constexpr auto kIkBudget = std::chrono::milliseconds(2);

void Check(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "request_fuzzer: %s\n", what);
  std::abort();
}

// Errors a client may get for a bad request; INTERNAL and UNKNOWN mean the server lost its way.
void CheckRefusal(const Status& status, const char* what) {
  if (status.code() != StatusCode::kInternal && status.code() != StatusCode::kUnknown &&
      status.code() != StatusCode::kOk) {
    return;
  }
  std::fprintf(stderr, "request_fuzzer: %s: improper error %s\n", what, status.ToString().c_str());
  std::abort();
}

class Silent : public google::protobuf::io::ErrorCollector {
 public:
  void AddError(int, google::protobuf::io::ColumnNumber, const std::string&) override {}
};

bool Parse(const std::string& bytes, bool text, google::protobuf::Message& message) {
  if (!text) return message.ParseFromString(bytes);
  Silent silent;
  google::protobuf::TextFormat::Parser parser;
  parser.RecordErrorsTo(&silent);
  return parser.ParseFromString(bytes, &message);
}

std::string SceneOf(const ScanFuzzWorld& world, const std::string& id) { return id == "scene" ? world.scene_id : id; }

std::string MountOf(const ScanFuzzWorld& world, const std::string& id) {
  const auto named = world.mounts.find(id);
  return named != world.mounts.end() ? named->second : id;
}

class NoCampaigns : public vscan::service::CampaignRecords {
 public:
  vscan::StatusOr<vscan::service::CampaignRecord> Get(const std::string& job_id) override {
    return vscan::NotFound("campaign_job_id", "no job '" + job_id + "'");
  }
};

vscan::store::JobCatalogue& Jobs(const ScanFuzzWorld& world) {
  static std::unique_ptr<vscan::store::JobCatalogue> jobs = [&] {
    auto opened = vscan::store::JobCatalogue::Open(world.data_dir / "fuzz_jobs.db");
    Check(opened.ok(), "cannot open the job catalogue");
    return std::move(opened).value();
  }();
  return *jobs;
}

void Campaign(ScanFuzzWorld& world, vscan::v1::CampaignSpec spec) {
  spec.set_scene_id(SceneOf(world, spec.scene_id()));
  spec.set_mount_id(MountOf(world, spec.mount_id()));
  // Only dry runs: a full check solves IK for the rest pose of every mount, which fuzzes slowly.
  const auto plan = vscan::api::ValidateCampaign(spec, *world.context, true);
  if (!plan.ok()) return CheckRefusal(plan.status(), "campaign spec");
  Check(!plan->viewpoints.empty(), "campaign without viewpoints");
  Check(plan->viewpoints.size() <= vscan::service::kMaxCampaignViewpoints, "campaign beyond kMaxCampaignViewpoints");
  Check(plan->rotations >= 1 && plan->rotations <= vscan::service::kMaxCampaignRotations,
        "campaign rotations beyond kMaxCampaignRotations");
  Check(plan->scans_total() <= vscan::service::kMaxCampaignSteps, "campaign beyond kMaxCampaignSteps");
  Check(std::isfinite(plan->AngleDeg(plan->rotations - 1)), "campaign table angle not finite");
  for (const auto& viewpoint : plan->viewpoints) {
    Check(viewpoint.position.allFinite() && viewpoint.target.allFinite(), "campaign viewpoint not finite");
  }
  const auto& camera = plan->scan.camera;
  Check(uint64_t{camera.width} * camera.height <= world.options.limits.max_rays_per_scan,
        "campaign scans beyond max_rays_per_scan");
}

void BinFill(ScanFuzzWorld& world, vscan::v1::BinFillSpec spec) {
  spec.set_scene_id(SceneOf(world, spec.scene_id()));
  const auto plan = vscan::api::ValidateBinFill(spec, *world.context, true);
  if (!plan.ok()) return CheckRefusal(plan.status(), "bin fill spec");
  Check(plan->parts.size() == plan->geometry.size(), "bin fill parts and geometry differ");
}

void Model(ScanFuzzWorld& world, const vscan::v1::ModelSpec& spec) {
  NoCampaigns campaigns;
  const auto plan = vscan::api::ValidateModel(spec, *world.context, campaigns);
  if (!plan.ok()) CheckRefusal(plan.status(), "model spec");
}

void Dataset(ScanFuzzWorld& world, const vscan::v1::DatasetSpec& spec) {
  const auto dataset = vscan::api::ValidateDataset(spec, *world.context, Jobs(world));
  if (!dataset.ok()) return CheckRefusal(dataset.status(), "dataset spec");
  Check(dataset->setup != nullptr, "accepted dataset without a setup");
}

void Localize(const vscan::v1::LocalizeRequest& request) {
  const auto plan = vscan::api::ParseLocalizeRequest(request);
  if (!plan.ok()) return CheckRefusal(plan.status(), "localize request");
  Check(plan->points.size() <= vscan::api::kMaxInlinePoints, "localize beyond kMaxInlinePoints");
  Check(plan->normals.empty() || plan->normals.size() == plan->points.size(), "localize normals do not match");
  for (const auto& p : plan->points) Check(p.allFinite(), "localize accepted a non-finite point");
  Check(!plan->parts.empty() && plan->parts.size() <= vscan::api::kMaxLocalizeParts, "localize part count");
  for (const auto& part : plan->parts) {
    Check(std::isfinite(part.scale) && part.scale > 0, "localize accepted a bad scale");
    Check(part.max_instances <= vscan::api::kMaxLocalizeInstances, "localize accepted too many instances");
  }
}

void Score(const vscan::v1::ScorePosesRequest& request) {
  const auto plan = vscan::api::ParseScorePosesRequest(request);
  if (!plan.ok()) return CheckRefusal(plan.status(), "score poses request");
  Check(plan->parts.size() <= vscan::api::kMaxScoredParts, "scoring beyond kMaxScoredParts");
  Check(plan->estimates.size() <= vscan::api::kMaxScoredPoses && plan->truth.size() <= vscan::api::kMaxScoredPoses,
        "scoring beyond kMaxScoredPoses");
}

// What RobotService.ForwardKinematics does with a mount (the call's own steps, without gRPC).
void ForwardKinematics(ScanFuzzWorld& world, const vscan::v1::ForwardKinematicsRequest& request) {
  const auto target = vscan::service::ResolveArm(*world.robots, "", MountOf(world, request.mount_id()));
  if (!target.ok()) return CheckRefusal(target.status(), "forward kinematics mount");
  const Eigen::VectorXd q =
      Eigen::Map<const Eigen::VectorXd>(request.joint_positions().data(), request.joint_positions().size());
  std::optional<uint64_t> seed;
  if (request.apply_encoder_noise()) seed = request.encoder_noise_seed();
  const auto state =
      vscan::robot_registry::CommandJoints(*target->chain, target->placement, q, "joint_positions", seed);
  if (!state.ok()) return CheckRefusal(state.status(), "forward kinematics");
  Check(state->achieved.allFinite(), "forward kinematics: non-finite achieved joints");
  const auto links = vscan::robot::ChainLinkPoses(*target->chain, q);
  Check(links.ok(), "forward kinematics: link poses failed after CommandJoints accepted");
}

// What RobotService.InverseKinematics does with a mount, without the collision retries.
void InverseKinematics(ScanFuzzWorld& world, const vscan::v1::InverseKinematicsRequest& request) {
  auto plan = vscan::api::ParseInverseKinematicsRequest(request);
  if (!plan.ok()) return CheckRefusal(plan.status(), "inverse kinematics request");
  const auto& settings = plan->settings;
  Check(std::isfinite(settings.position_tolerance) && settings.position_tolerance > 0 &&
            settings.position_tolerance <= vscan::api::kMaxIkPositionTolerance,
        "inverse kinematics accepted a bad tolerance");
  Check(std::isfinite(settings.orientation_tolerance) && settings.orientation_tolerance > 0,
        "inverse kinematics accepted a bad orientation tolerance");
  Check(settings.time_budget.count() > 0 &&
            settings.time_budget <= std::chrono::milliseconds(static_cast<int64_t>(vscan::api::kMaxIkTimeoutMs)),
        "inverse kinematics accepted a time budget past kMaxIkTimeoutMs");
  const auto target = vscan::service::ResolveArm(*world.robots, "", MountOf(world, request.mount_id()));
  if (!target.ok()) return CheckRefusal(target.status(), "inverse kinematics mount");
  vscan::robot_registry::IkSettings quick = settings;
  quick.time_budget = std::min<std::chrono::microseconds>(settings.time_budget, kIkBudget);
  const Eigen::VectorXd seed = Eigen::Map<const Eigen::VectorXd>(request.seed().data(), request.seed().size());
  const auto answer =
      vscan::robot_registry::SolveInPlacement(*target->chain, target->placement, plan->goal, seed, quick);
  if (!answer.ok()) return CheckRefusal(answer.status(), "inverse kinematics");
  Check(answer->result.joint_positions.allFinite(), "inverse kinematics: non-finite joints");
  Check(std::isfinite(answer->miss_distance), "inverse kinematics: non-finite miss distance");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Binary inputs with invalid UTF-8 in string fields would log a line each.
  google::protobuf::SetLogHandler(nullptr);
  (void)World();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  ScanFuzzWorld& world = World();
  const int kind = data[0] % kKinds;
  const bool text = (data[0] / kKinds) % 2 == 0;
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  switch (kind) {
    case 0: {
      vscan::v1::CampaignSpec spec;
      if (Parse(bytes, text, spec)) Campaign(world, std::move(spec));
      break;
    }
    case 1: {
      vscan::v1::BinFillSpec spec;
      if (Parse(bytes, text, spec)) BinFill(world, std::move(spec));
      break;
    }
    case 2: {
      vscan::v1::ModelSpec spec;
      if (Parse(bytes, text, spec)) Model(world, spec);
      break;
    }
    case 3: {
      vscan::v1::DatasetSpec spec;
      if (Parse(bytes, text, spec)) Dataset(world, spec);
      break;
    }
    case 4: {
      vscan::v1::LocalizeRequest request;
      if (Parse(bytes, text, request)) Localize(request);
      break;
    }
    case 5: {
      vscan::v1::ScorePosesRequest request;
      if (Parse(bytes, text, request)) Score(request);
      break;
    }
    case 6: {
      vscan::v1::ForwardKinematicsRequest request;
      if (Parse(bytes, text, request)) ForwardKinematics(world, request);
      break;
    }
    default: {
      vscan::v1::InverseKinematicsRequest request;
      if (Parse(bytes, text, request)) InverseKinematics(world, request);
      break;
    }
  }
  return 0;
}
