#include "api/model/model_spec.h"

#include "api/campaign/campaign_spec.h"
#include "api/transport/validate.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

StatusOr<service::InitialPoseMode> InitialPose(v1::InitialPose value) {
  switch (value) {
    case v1::INITIAL_POSE_UNSPECIFIED: return service::InitialPoseMode::kAuto;
    case v1::INITIAL_POSE_KNOWN: return service::InitialPoseMode::kKnown;
    case v1::INITIAL_POSE_FEATURES: return service::InitialPoseMode::kFeatures;
    default: break;
  }
  return InvalidArgument("alignment.initial_pose", "unknown value " + std::to_string(static_cast<int>(value)));
}

StatusOr<service::ReconstructionKind> Method(v1::ReconstructionMethod value) {
  switch (value) {
    case v1::RECONSTRUCTION_METHOD_UNSPECIFIED: return service::ReconstructionKind::kAuto;
    case v1::RECONSTRUCTION_METHOD_TSDF: return service::ReconstructionKind::kTsdf;
    case v1::RECONSTRUCTION_METHOD_POISSON: return service::ReconstructionKind::kPoisson;
    default: break;
  }
  return InvalidArgument("reconstruction.method", "unknown value " + std::to_string(static_cast<int>(value)));
}

Status OptionalId(const std::string& id, const char* field) {
  return id.empty() ? Status::Ok() : RequireId(id, field);
}

// The stage options a ModelSpec and a CampaignSpec share, with the same field names.
template <typename Spec>
Status ReadStageOptions(const Spec& spec, service::ModelRequest& request) {
  const v1::AlignmentOptions& alignment = spec.alignment();
  ASSIGN_OR_RETURN(request.initial_pose, InitialPose(alignment.initial_pose()));
  request.voxel_size = alignment.voxel_size();
  request.max_correspondence_distance = alignment.max_correspondence_distance();
  request.min_fitness = alignment.min_fitness();
  request.skip_pose_graph = alignment.skip_pose_graph();

  request.reconstruct = spec.reconstruct();
  ASSIGN_OR_RETURN(request.reconstruction, Method(spec.reconstruction().method()));
  request.reconstruction_voxel_size = spec.reconstruction().voxel_size();
  request.poisson_depth = spec.reconstruction().poisson_depth();

  request.evaluate = spec.evaluate();
  request.tau = spec.evaluation().tau();
  request.next_best_views = spec.evaluation().next_best_views();
  request.skip_next_best_views = spec.evaluation().skip_next_best_views();
  return Status::Ok();
}

}  // namespace

StatusOr<service::ModelRequest> ModelRequestFromProto(const v1::ModelSpec& spec) {
  service::ModelRequest request;
  RETURN_IF_ERROR(CheckText(spec.name(), "name"));
  request.name = spec.name();
  if (spec.cloud_ids_size() > static_cast<int>(service::kMaxModelClouds)) {
    return InvalidArgument("cloud_ids", "at most " + std::to_string(service::kMaxModelClouds) + " clouds, not " +
                                            std::to_string(spec.cloud_ids_size()));
  }
  for (int i = 0; i < spec.cloud_ids_size(); ++i) {
    RETURN_IF_ERROR(RequireId(spec.cloud_ids(i), "cloud_ids[" + std::to_string(i) + "]"));
    request.cloud_ids.push_back(spec.cloud_ids(i));
  }
  RETURN_IF_ERROR(OptionalId(spec.campaign_job_id(), "campaign_job_id"));
  RETURN_IF_ERROR(OptionalId(spec.scene_id(), "scene_id"));
  RETURN_IF_ERROR(OptionalId(spec.mount_id(), "mount_id"));
  request.campaign_job_id = spec.campaign_job_id();
  request.scene_id = spec.scene_id();
  request.mount_id = spec.mount_id();

  request.skip_alignment = spec.skip_alignment();
  RETURN_IF_ERROR(ReadStageOptions(spec, request));

  if (spec.has_crop()) {
    if (!spec.crop().has_min()) return InvalidArgument("crop.min", "required when crop is set");
    if (!spec.crop().has_max()) return InvalidArgument("crop.max", "required when crop is set");
    request.crop = service::ModelBox{FromProto(spec.crop().min()), FromProto(spec.crop().max())};
  }
  return request;
}

StatusOr<service::ModelRequest> ModelRequestFromCampaign(const v1::CampaignSpec& spec) {
  service::ModelRequest request;
  request.name = spec.name();
  RETURN_IF_ERROR(ReadStageOptions(spec, request));
  return request;
}

StatusOr<service::ModelPlan> ValidateModel(const v1::ModelSpec& spec, service::ServiceContext& context,
                                           service::CampaignRecords& campaigns) {
  auto request = ModelRequestFromProto(spec);
  if (!request.ok()) return InSpec(request.status());
  auto plan = service::PlanModel(context, campaigns, *request);
  if (!plan.ok()) return InSpec(plan.status());
  return plan;
}

}  // namespace vscan::api
