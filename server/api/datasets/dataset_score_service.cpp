// JobService.ScoreDatasetResults: a BOP results file scored against a finished dataset job's
// ground truth (service/datasets/dataset_scoring.h).

#include <chrono>
#include <string>

#include "api/job/job_service.h"
#include "api/datasets/dataset_spec.h"
#include "api/localization/grasp_scoring_request.h"
#include "api/transport/cancellable_unary.h"
#include "api/transport/validate.h"
#include "service/datasets/dataset_job_run.h"
#include "service/datasets/dataset_scoring.h"

namespace vscan::api {
namespace {

// Below the server's 4 MiB message bound, so that a larger file is refused here, naming the field.
constexpr size_t kMaxResultsCsvBytes = 3 << 20;

void RecallToProto(const service::RecallCounts& counts, bool per_threshold, bool grasps, v1::DatasetRecall* out) {
  out->set_valid_instances(counts.valid_instances);
  if (grasps) {
    out->set_grasp_holds(counts.grasp_holds);
    if (const auto success = counts.GraspSuccess()) out->set_grasp_success(*success);
  }
  out->set_estimates(counts.estimates);
  out->set_add_correct(counts.add_correct);
  if (const auto recall = counts.AddRecall()) out->set_add_recall(*recall);
  if (const auto recall = counts.MssdAverageRecall()) out->set_mssd_average_recall(*recall);
  if (per_threshold) {
    for (const double recall : counts.MssdRecalls()) out->add_mssd_recalls(recall);
  }
}

void DatasetScoreToResponse(const service::DatasetScore& score, bool grasps,
                            v1::ScoreDatasetResultsResponse* response) {
  RecallToProto(score.tally.overall(), true, grasps, response->mutable_overall());
  for (const auto& [obj_id, counts] : score.tally.objects()) {
    v1::DatasetObjectScore* object = response->add_objects();
    object->set_obj_id(obj_id);
    if (const auto model = score.models.find(obj_id); model != score.models.end()) {
      object->set_diameter_mm(model->second.diameter_mm);
      object->set_uses_add_s(model->second.symmetries.any());
    }
    RecallToProto(counts, true, grasps, object->mutable_recall());
  }
  for (const auto& [scene_id, counts] : score.tally.scenes()) {
    v1::DatasetSceneScore* scene = response->add_scenes();
    scene->set_scene_id(scene_id);
    RecallToProto(counts, false, grasps, scene->mutable_recall());
  }
  response->set_scene_count(score.scene_count);
  response->set_image_count(score.images);
  response->set_true_instances(score.true_instances);
  response->set_rows(score.rows);
  response->set_ignored_rows(score.ignored_rows);
  for (const auto& [scene_id, im_id] : score.ignored_images) {
    response->add_ignored_images(std::to_string(scene_id) + "/" + std::to_string(im_id));
  }
  response->set_add_threshold(score.add_threshold);
  for (const double threshold : score.mssd_thresholds) response->add_mssd_thresholds(threshold);
  response->set_min_visible_fraction(score.min_visible_fraction);
}

}  // namespace

grpc::ServerUnaryReactor* JobService::ScoreDatasetResults(grpc::CallbackServerContext* ctx,
                                                          const v1::ScoreDatasetResultsRequest* request,
                                                          v1::ScoreDatasetResultsResponse* response) {
  // Reads every scene's ground truth and scores each image: on the workers, stopped by cancel.
  return RunCancellableUnary(
      ctx, context_.options.token, "ScoreDatasetResults", context_.workers,
      [=, this](const std::atomic<bool>& cancel) -> Status {
        const auto start = std::chrono::steady_clock::now();
        RETURN_IF_ERROR(RequireId(request->job_id(), "job_id"));
        ASSIGN_OR_RETURN(std::optional<service::GraspScoring> grasp,
                         ParseGraspScoring(request->has_gripper(), request->gripper(), request->grasp_options(),
                                           request->has_up(), request->up()));
        if (request->results_csv().size() > kMaxResultsCsvBytes) {
          return ResourceExhausted("results_csv", std::to_string(request->results_csv().size()) +
                                                      " bytes, more than the " +
                                                      std::to_string(kMaxResultsCsvBytes >> 20) + " MiB one call takes");
        }
        const StatusOr<store::JobRecord> job = tracker_.catalogue().GetJob(request->job_id());
        if (!job.ok() && job.status().code() == StatusCode::kNotFound) {
          return NotFound("job_id", "no job '" + request->job_id() + "'");
        }
        RETURN_IF_ERROR(job.status());
        const std::string directory = DatasetDirectoryOf(*job);
        if (directory.empty()) {
          return FailedPrecondition("job_id", "job '" + request->job_id() + "' is a " + job->kind + " job, not a dataset");
        }
        if (job->state != store::JobState::kSucceeded) {
          return FailedPrecondition("job_id", "job '" + request->job_id() + "' is " + store::JobStateName(job->state) +
                                                  ": only a finished dataset is scored");
        }
        ASSIGN_OR_RETURN(const std::vector<service::dataset::BopResultRow> rows,
                         service::dataset::ParseBopResultsCsv(request->results_csv(), "results_csv"));
        service::DatasetScoringOptions options;
        options.cancel = &cancel;
        options.grasp = std::move(grasp);
        const bool grasps = options.grasp.has_value();
        StatusOr<service::DatasetScore> score = service::ScoreDatasetResults(
            service::DatasetJobRoot(context_.options.data_dir, directory), rows, options, "results_csv");
        if (!score.ok() && score.status().code() == StatusCode::kFailedPrecondition) {
          return FailedPrecondition("job_id", "job '" + request->job_id() + "': " + score.status().message());
        }
        RETURN_IF_ERROR(score.status());
        DatasetScoreToResponse(*score, grasps, response);
        response->set_score_ms(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        return Status::Ok();
      });
}

}  // namespace vscan::api
