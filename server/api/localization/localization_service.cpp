#include "api/localization/localization_service.h"

#include "api/localization/localize_progress_reactor.h"
#include "api/localization/localization_request.h"
#include "api/transport/cancellable_unary.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

void ToResponse(const service::LocalizeOutcome& outcome, v1::LocalizeResponse* response) {
  for (const localization::LocalizedInstance& instance : outcome.result.instances) {
    v1::PoseEstimate* estimate = response->add_estimates();
    vscan::ToProto(instance.world_from_part, estimate->mutable_world_from_part());
    estimate->set_score(instance.score);
    estimate->set_explained_points(instance.explained_points);
    estimate->set_part(static_cast<uint32_t>(instance.part));
  }
  response->set_frame(outcome.frame == store::CloudFrame::kSensor ? v1::FRAME_SENSOR : v1::FRAME_WORLD);
  response->set_points(outcome.points);
  response->set_support_plane_points(outcome.result.support_plane_points);
  for (size_t i = 0; i < outcome.result.parts.size(); ++i) {
    const localization::PartSearch& search = outcome.result.parts[i];
    v1::PartSearchSummary* summary = response->add_parts();
    summary->set_part(static_cast<uint32_t>(i));
    summary->set_voxel_size(search.voxel_size);
    summary->set_found(search.found);
    summary->set_stop_reason(search.stop_reason);
  }
  // The fields of the single-part form: the first part's figures.
  if (!outcome.result.parts.empty()) {
    response->set_voxel_size(outcome.result.parts.front().voxel_size);
    response->set_stop_reason(outcome.result.parts.front().stop_reason);
  }
  response->set_localize_ms(outcome.localize_ms);
}

Status RunLocalizeRequest(service::ServiceContext& context, const v1::LocalizeRequest& request,
                          const std::atomic<bool>& cancel, const localization::LocalizeProgressCallback& progress,
                          v1::LocalizeResponse* response) {
  ASSIGN_OR_RETURN(const service::LocalizePlan plan, ParseLocalizeRequest(request));
  ASSIGN_OR_RETURN(const service::LocalizeOutcome outcome,
                   service::RunLocalize(context.registry, service::StoredCloudsOf(context), plan, &cancel, progress,
                                       context.part_models.get()));
  ToResponse(outcome, response);
  return Status::Ok();
}

void ToResponse(const service::ScoringPlan& plan, const service::PoseScores& scores,
                const v1::ScorePosesRequest& request, v1::ScorePosesResponse* response) {
  const localization::ScanScore& score = scores.scan;
  for (size_t p = 0; p < score.parts.size(); ++p) {
    const localization::PartScore& part = score.parts[p];
    v1::PartScore* out = response->add_parts();
    out->set_part(part.part_id);
    out->set_mesh_id(plan.parts[part.part_id].mesh_id);
    out->set_diameter(part.diameter);
    out->set_uses_add_s(part.uses_add_s);
    out->set_valid_instances(part.valid_instances);
    out->set_estimates(part.estimates);
    out->set_add_correct(part.add_correct);
    if (part.add_recall) out->set_add_recall(*part.add_recall);
    if (part.mssd_average_recall) out->set_mssd_average_recall(*part.mssd_average_recall);
    for (const double recall : part.mssd_recalls) out->add_mssd_recalls(recall);
    for (const localization::InstanceResult& instance : part.instances) {
      v1::PoseMatch* match = out->add_matches();
      match->set_truth_index(static_cast<uint32_t>(instance.true_index));
      match->set_instance_id(request.truth(static_cast<int>(instance.true_index)).instance_id());
      if (instance.estimate_index) match->set_estimate_index(static_cast<uint32_t>(*instance.estimate_index));
      match->set_add_error(instance.add_error);
      match->set_mssd_error(instance.mssd_error);
    }
    if (scores.grasp) {
      const service::PartGraspScore& grasp = scores.grasp->parts[p];
      for (size_t i = 0; i < grasp.instances.size(); ++i) {
        if (!grasp.instances[i]) continue;
        out->mutable_matches(static_cast<int>(i))->set_grasp_holds(grasp.instances[i]->holds);
        out->mutable_matches(static_cast<int>(i))->set_grasp_failure(grasp.instances[i]->failure);
      }
      out->set_grasp_holds(grasp.holds);
      if (grasp.success) out->set_grasp_success(*grasp.success);
    }
  }
  if (scores.grasp) {
    response->set_grasp_holds(scores.grasp->holds);
    if (scores.grasp->success) response->set_grasp_success(*scores.grasp->success);
  }
  response->set_valid_instances(score.valid_instances);
  if (score.add_recall) response->set_add_recall(*score.add_recall);
  if (score.mssd_average_recall) response->set_mssd_average_recall(*score.mssd_average_recall);
  response->set_add_threshold(plan.options.add_threshold);
  const std::vector<double> thresholds =
      plan.options.mssd_thresholds.empty() ? localization::BopMssdThresholds() : plan.options.mssd_thresholds;
  for (const double threshold : thresholds) response->add_mssd_thresholds(threshold);
}

}  // namespace

grpc::ServerUnaryReactor* LocalizationService::Localize(grpc::CallbackServerContext* ctx,
                                                        const v1::LocalizeRequest* request,
                                                        v1::LocalizeResponse* response) {
  // Seconds of voting and ICP: on the workers that run scans, not on a gRPC thread.
  return RunCancellableUnary(ctx, context_.options.token, "Localize", context_.workers,
                             [=, this](const std::atomic<bool>& cancel) -> Status {
                               return RunLocalizeRequest(context_, *request, cancel, {}, response);
                             });
}

grpc::ServerWriteReactor<v1::LocalizeWithProgressResponse>* LocalizationService::LocalizeWithProgress(
    grpc::CallbackServerContext* ctx, const v1::LocalizeWithProgressRequest* request) {
  return LocalizeProgressReactor::Start(
      ctx, context_.options.token, context_.workers, stalled_readers_,
      [=, this](const std::atomic<bool>& cancel, const localization::LocalizeProgressCallback& progress,
                v1::LocalizeResponse* response) {
        return RunLocalizeRequest(context_, request->localize(), cancel, progress, response);
      });
}

grpc::ServerUnaryReactor* LocalizationService::ScorePoses(grpc::CallbackServerContext* ctx,
                                                          const v1::ScorePosesRequest* request,
                                                          v1::ScorePosesResponse* response) {
  // MSSD over sampled symmetries: bounded by kMaxScoringWork, stopped by cancel and the deadline.
  return RunCancellableUnary(ctx, context_.options.token, "ScorePoses", context_.workers,
                             [=, this](const std::atomic<bool>& cancel) -> Status {
                               ASSIGN_OR_RETURN(const service::ScoringPlan plan, ParseScorePosesRequest(*request));
                               ASSIGN_OR_RETURN(const service::PoseScores score,
                                                service::ScorePosesWithGrasps(context_.registry, plan, &cancel));
                               ToResponse(plan, score, *request, response);
                               return Status::Ok();
                             });
}

}  // namespace vscan::api
