// JobService.SubmitPickingEstimates: a client's estimates for the step a picking job awaits.

#include <cmath>
#include <map>
#include <tuple>

#include <spdlog/spdlog.h>

#include "api/job/job_service.h"
#include "api/picking/picking_estimates_files.h"
#include "api/reports/report_convert.h"
#include "api/transport/unary.h"
#include "api/transport/validate.h"
#include "grasping/pick_checks.h"
#include "service/job/job_kind.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr int kMaxEstimates = 10000;

// The request's estimates in the world frame; INVALID_ARGUMENT naming the estimate's field.
StatusOr<std::vector<picking::Estimate>> ParseEstimates(const v1::SubmitPickingEstimatesRequest& request,
                                                        const service::AwaitedStep& awaited) {
  std::map<std::string, size_t> type_of;
  std::string names;
  for (size_t t = 0; t < awaited.part_names.size(); ++t) {
    type_of.emplace(awaited.part_names[t], t);
    names += (t ? ", " : "") + awaited.part_names[t];
  }
  std::vector<picking::Estimate> out;
  std::map<std::tuple<size_t, std::vector<double>>, int> seen;
  double sweeps = 0;  // the plan tests every grasp of every estimate at worst
  for (int i = 0; i < request.estimates_size(); ++i) {
    const v1::PickingEstimate& estimate = request.estimates(i);
    const std::string field = "estimates[" + std::to_string(i) + "]";
    const auto type = type_of.find(estimate.part());
    if (type == type_of.end()) {
      return InvalidArgument(field + ".part", "'" + estimate.part().substr(0, 64) + "' is none of the bin's parts (" +
                                                  names + ")");
    }
    if (estimate.has_world_from_part() == estimate.has_camera_from_part()) {
      return InvalidArgument(field + ".world_from_part", "give exactly one of world_from_part and camera_from_part");
    }
    Pose3 world_from_part;
    if (estimate.has_world_from_part()) {
      ASSIGN_OR_RETURN(world_from_part, PoseFromProto(estimate.world_from_part(), field + ".world_from_part"));
    } else {
      ASSIGN_OR_RETURN(const Pose3 camera_from_part,
                       PoseFromProto(estimate.camera_from_part(), field + ".camera_from_part"));
      ASSIGN_OR_RETURN(world_from_part,
                       PoseFromMatrix((awaited.world_from_sensor * camera_from_part).matrix(), field + ".camera_from_part"));
    }
    if (!std::isfinite(estimate.score())) return InvalidArgument(field + ".score", "must be finite");
    const Eigen::Matrix4d m = world_from_part.matrix();
    const auto [earlier, fresh] = seen.emplace(std::make_tuple(type->second, std::vector<double>(m.data(), m.data() + 16)), i);
    if (!fresh) {
      return InvalidArgument(field, "the same part and pose as estimates[" + std::to_string(earlier->second) + "]");
    }
    out.push_back({type->second, world_from_part, estimate.score()});
    if (type->second < awaited.grasps_per_type.size()) sweeps += double(awaited.grasps_per_type[type->second]);
  }
  if (sweeps > grasping::kMaxSweepChecks) {
    return ResourceExhausted("estimates", std::to_string(out.size()) + " estimates would have the step test " +
                                              std::to_string(size_t(sweeps)) +
                                              " grasps, at most 1e6 (send fewer, or lower spec.grasp_options.max_grasps)");
  }
  return out;
}

v1::PickingStepTruth StoredForm(const service::AwaitedStep& awaited, const std::vector<picking::Estimate>& estimates) {
  v1::PickingStepTruth out;
  out.set_step(static_cast<uint32_t>(awaited.step));
  for (const auto& [type, instance] : awaited.pile) {
    v1::PickingPose* part = out.add_parts();
    part->set_part(awaited.part_names[type]);
    part->set_instance(static_cast<uint32_t>(instance));
  }
  for (const picking::Estimate& estimate : estimates) {
    v1::PickingPose* pose = out.add_estimates();
    pose->set_part(awaited.part_names[estimate.type]);
    pose->set_score(estimate.score);
    AddMatrix(estimate.world_from_part, pose->mutable_world_from_part());
  }
  return out;
}

}  // namespace

void JobService::ShowAwaitedEstimates(v1::Job* job) const {
  job->clear_awaiting_estimates();
  const auto awaited = picking_estimates_.Awaiting(job->job_id());
  if (!awaited) return;
  v1::AwaitedEstimates* out = job->mutable_awaiting_estimates();
  out->set_step(static_cast<uint32_t>(awaited->step));
  out->set_scan_artifact(awaited->scan_artifact);
  vscan::ToProto(awaited->world_from_sensor, out->mutable_world_from_sensor());
  for (const std::string& name : awaited->part_names) out->add_part_names(name);
}

grpc::ServerUnaryReactor* JobService::SubmitPickingEstimates(grpc::CallbackServerContext* ctx,
                                                             const v1::SubmitPickingEstimatesRequest* request,
                                                             v1::SubmitPickingEstimatesResponse* response) {
  return RunBlockingUnary(
      ctx, context_.options.token, "SubmitPickingEstimates", context_.call_workers, [=, this]() -> Status {
        const std::string& job_id = request->job_id();
        RETURN_IF_ERROR(RequireId(job_id, "job_id"));
        if (request->estimates_size() > kMaxEstimates) {
          return ResourceExhausted("estimates", "at most " + std::to_string(kMaxEstimates) + " per step, got " +
                                                    std::to_string(request->estimates_size()));
        }
        auto job = tracker_.catalogue().GetJob(job_id);
        if (!job.ok()) return Status(job.status().code(), "job_id: " + job.status().message());
        if (job->kind != service::JobKindName(service::JobKind::kPicking)) {
          return FailedPrecondition("job_id", "job '" + job_id + "' is a " + job->kind + " job, not a picking job");
        }
        v1::PickingSpec spec;
        if (!spec.ParseFromString(job->spec)) return DataLoss("job_id: job '" + job_id + "': its stored spec does not parse");
        if (spec.perception() != v1::PICKING_PERCEPTION_CLIENT) {
          return FailedPrecondition("job_id", "job '" + job_id + "' does not take client estimates (its perception is " +
                                                  v1::PickingPerception_Name(spec.perception()) + ")");
        }
        if (job->state != store::JobState::kRunning) {
          return FailedPrecondition("job_id", "job '" + job_id + "' is not running (" +
                                                  store::JobStateName(job->state) + ")");
        }
        const auto awaited = picking_estimates_.Awaiting(job_id);
        if (!awaited) return FailedPrecondition("step", "job '" + job_id + "' awaits no estimates now");
        if (awaited->step != request->step()) {
          return FailedPrecondition("step", "job '" + job_id + "' awaits the estimates of step " +
                                                std::to_string(awaited->step) + ", not of step " +
                                                std::to_string(request->step()));
        }
        ASSIGN_OR_RETURN(std::vector<picking::Estimate> estimates, ParseEstimates(*request, *awaited));
        RETURN_IF_ERROR(picking_estimates_.Claim(job_id, awaited->step));
        const PickingEstimatesFiles files(context_.options.data_dir, job_id);
        const Status stored = files.Write(StoredForm(*awaited, estimates));
        if (!stored.ok()) {
          picking_estimates_.Release(job_id, awaited->step);
          return Unavailable("step " + std::to_string(awaited->step) + ": the estimates could not be stored: " +
                             stored.message());
        }
        const size_t count = estimates.size();
        if (!picking_estimates_.Deliver(job_id, awaited->step, std::move(estimates))) {
          spdlog::info("job {}: stopped waiting before step {}'s estimates came; they are kept for a resume", job_id,
                       awaited->step);
        }
        response->set_accepted(static_cast<uint32_t>(count));
        return Status::Ok();
      });
}

}  // namespace vscan::api
