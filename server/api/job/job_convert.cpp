#include "api/job/job_convert.h"

#include <google/protobuf/util/time_util.h>

#include "api/job/job_kinds.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {

v1::JobState ToProto(store::JobState state) {
  switch (state) {
    case store::JobState::kQueued: return v1::JOB_STATE_QUEUED;
    case store::JobState::kRunning: return v1::JOB_STATE_RUNNING;
    case store::JobState::kSucceeded: return v1::JOB_STATE_SUCCEEDED;
    case store::JobState::kFailed: return v1::JOB_STATE_FAILED;
    case store::JobState::kCancelled: return v1::JOB_STATE_CANCELLED;
    case store::JobState::kInterrupted: return v1::JOB_STATE_INTERRUPTED;
  }
  return v1::JOB_STATE_UNSPECIFIED;
}

void SetTime(int64_t ms, google::protobuf::Timestamp* out) {
  *out = google::protobuf::util::TimeUtil::MillisecondsToTimestamp(ms);
}

Status ToProto(const store::ArtifactRecord& artifact, v1::Artifact* out) {
  out->set_artifact_id(artifact.artifact_id);
  out->set_name(artifact.name);
  out->set_media_type(artifact.media_type);
  out->set_size_bytes(artifact.size_bytes);
  if (!artifact.info.empty() && !out->mutable_scan()->ParseFromString(artifact.info)) {
    return DataLoss("job catalogue: artifact '" + artifact.artifact_id + "' has an unreadable description");
  }
  return Status::Ok();
}

Status ToProto(const store::JobRecord& job, v1::Job* out) {
  out->set_job_id(job.job_id);
  out->set_kind(job.kind);
  out->set_state(ToProto(job.state));
  out->set_progress(job.steps_total ? static_cast<double>(job.steps_done) / job.steps_total
                                    : (job.state == store::JobState::kSucceeded ? 1.0 : 0.0));
  out->set_message(job.message);
  out->set_steps_done(job.steps_done);
  out->set_steps_total(job.steps_total);
  SetTime(job.create_time_ms, out->mutable_create_time());
  SetTime(job.update_time_ms, out->mutable_update_time());
  if (const JobKindRow* kind = FindJobKind(job.kind); kind && !kind->read_spec(job.spec, out)) {
    return DataLoss("job catalogue: job '" + job.job_id + "' has an unreadable " + std::string(kind->spec_noun));
  }
  for (const store::ArtifactRecord& artifact : job.artifacts) RETURN_IF_ERROR(ToProto(artifact, out->add_artifacts()));
  return Status::Ok();
}

void ToProto(const service::ScanAlignmentRecord& scan, v1::ScanAlignment* out) {
  out->set_cloud_id(scan.cloud_id);
  out->set_name(scan.name);
  out->set_union_points(scan.union_points);
  out->set_index(scan.index);
  out->set_aligned(scan.aligned);
  out->set_reason(scan.reason);
  vscan::ToProto(scan.model_from_sensor, out->mutable_pose());
  out->set_fitness(scan.fitness);
  out->set_inlier_rmse(scan.inlier_rmse);
  out->set_has_error(scan.has_error);
  if (scan.has_error) {
    out->set_rotation_error_deg(scan.rotation_error_deg);
    out->set_translation_error_m(scan.translation_error_m);
    out->set_initial_rotation_error_deg(scan.initial_rotation_error_deg);
    out->set_initial_translation_error_m(scan.initial_translation_error_m);
  }
}

}  // namespace vscan::api
