#include "api/localization/localization_request.h"

#include <cmath>
#include <cstring>
#include <string>

#include "api/localization/grasp_scoring_request.h"
#include "api/transport/validate.h"
#include "vscan/common/physical_limits.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

std::string Indexed(const std::string& field, size_t i) { return field + "[" + std::to_string(i) + "]"; }

StatusOr<std::vector<Eigen::Vector3f>> UnpackVectors(const std::string& bytes, const std::string& field) {
  if (bytes.size() % 12 != 0) {
    return InvalidArgument(field, "length " + std::to_string(bytes.size()) + " is not a multiple of 12 bytes");
  }
  std::vector<Eigen::Vector3f> out(bytes.size() / 12);
  for (size_t i = 0; i < out.size(); ++i) {
    float xyz[3];
    std::memcpy(xyz, bytes.data() + 12 * i, sizeof(xyz));
    out[i] = Eigen::Vector3f(xyz[0], xyz[1], xyz[2]);
  }
  return out;
}

Status ParseInlinePoints(const v1::InlinePoints& points, service::LocalizePlan& plan) {
  if (points.positions().size() > 12 * kMaxInlinePoints) {
    return ResourceExhausted("points.positions", "more than " + std::to_string(kMaxInlinePoints) +
                                                     " points; upload the cloud (CloudService) and send its cloud_id");
  }
  ASSIGN_OR_RETURN(plan.points, UnpackVectors(points.positions(), "points.positions"));
  if (plan.points.empty()) return InvalidArgument("points.positions", "required (12 bytes per point)");
  for (size_t i = 0; i < plan.points.size(); ++i) {
    RETURN_IF_ERROR(CheckPosition(plan.points[i].cast<double>(), Indexed("points.positions", i)));
  }
  if (points.normals().empty()) return Status::Ok();
  ASSIGN_OR_RETURN(plan.normals, UnpackVectors(points.normals(), "points.normals"));
  if (plan.normals.size() != plan.points.size()) {
    return InvalidArgument("points.normals", std::to_string(plan.normals.size()) + " normals for " +
                                                 std::to_string(plan.points.size()) + " points");
  }
  for (size_t i = 0; i < plan.normals.size(); ++i) {
    const float norm = plan.normals[i].norm();
    if (!std::isfinite(norm) || std::abs(norm - 1.0f) > 0.01f) {
      return InvalidArgument(Indexed("points.normals", i), "not a unit vector");
    }
  }
  return Status::Ok();
}

Status ParseLocalizeOptions(const v1::LocalizeOptions& options, service::LocalizePlan& plan) {
  localization::LocalizerOptions& out = plan.options;
  if (options.max_instances() > kMaxLocalizeInstances) {
    return InvalidArgument("options.max_instances", "at most " + std::to_string(kMaxLocalizeInstances));
  }
  if (options.max_instances() > 0) out.max_instances = options.max_instances();
  const double min_score = options.min_score();
  if (!std::isfinite(min_score) || min_score < 0 || min_score > 1) {
    return InvalidArgument("options.min_score", "must be within [0, 1] (0: the default 0.08)");
  }
  if (min_score > 0) out.min_score = min_score;
  const double voxel = options.voxel_size();
  if (voxel != 0 && !(std::isfinite(voxel) && voxel >= 1e-5 && voxel <= 1)) {
    return InvalidArgument("options.voxel_size", "must be 0 (from the part's size) or within [1e-5, 1] m");
  }
  out.voxel_size = voxel;
  switch (options.normal_source()) {
    case v1::NORMAL_SOURCE_UNSPECIFIED:
      plan.normal_source = service::NormalSource::kAuto;
      break;
    case v1::NORMAL_SOURCE_ESTIMATE:
      plan.normal_source = service::NormalSource::kEstimate;
      break;
    case v1::NORMAL_SOURCE_CLOUD:
      plan.normal_source = service::NormalSource::kCloud;
      break;
    default:
      return InvalidArgument("options.normal_source",
                             "unknown value " + std::to_string(static_cast<int>(options.normal_source())));
  }
  if (options.has_viewpoint()) {
    const Eigen::Vector3d viewpoint = FromProto(options.viewpoint());
    RETURN_IF_ERROR(CheckPosition(viewpoint, "options.viewpoint"));
    plan.viewpoint = viewpoint;
  }
  if (options.has_remove_support_plane()) out.remove_support_plane = options.remove_support_plane();
  return Status::Ok();
}

StatusOr<service::LocalizePartPlan> ParseLocalizePart(const v1::LocalizePart& part, const std::string& field) {
  service::LocalizePartPlan out;
  out.field = field + ".mesh_id";
  RETURN_IF_ERROR(RequireId(part.mesh_id(), out.field));
  out.mesh_id = part.mesh_id();
  ASSIGN_OR_RETURN(out.scale, ScaleOrDefault(part.scale(), field + ".scale"));
  if (part.max_instances() > kMaxLocalizeInstances) {
    return InvalidArgument(field + ".max_instances", "at most " + std::to_string(kMaxLocalizeInstances));
  }
  out.max_instances = part.max_instances();
  return out;
}

// Either the single part (mesh_id, scale) or the parts list; after the options, whose
// max_instances a part's 0 stands for.
Status ParseLocalizeParts(const v1::LocalizeRequest& request, service::LocalizePlan& plan) {
  if (request.parts_size() == 0) {
    service::LocalizePartPlan part;
    RETURN_IF_ERROR(RequireId(request.mesh_id(), "mesh_id"));
    part.mesh_id = request.mesh_id();
    ASSIGN_OR_RETURN(part.scale, ScaleOrDefault(request.scale(), "scale"));
    plan.parts.push_back(std::move(part));
    return Status::Ok();
  }
  if (!request.mesh_id().empty()) return InvalidArgument("parts", "give mesh_id (one part) or parts, not both");
  if (request.scale() != 0) return InvalidArgument("scale", "only with mesh_id; give each part's parts[i].scale");
  if (static_cast<size_t>(request.parts_size()) > kMaxLocalizeParts) {
    return InvalidArgument("parts", std::to_string(request.parts_size()) + " parts; at most " +
                                        std::to_string(kMaxLocalizeParts));
  }
  size_t instances = 0;
  for (int i = 0; i < request.parts_size(); ++i) {
    const std::string field = Indexed("parts", i);
    ASSIGN_OR_RETURN(service::LocalizePartPlan part, ParseLocalizePart(request.parts(i), field));
    for (size_t j = 0; j < plan.parts.size(); ++j) {
      if (plan.parts[j].mesh_id == part.mesh_id && plan.parts[j].scale == part.scale) {
        return InvalidArgument(field, "the same mesh and scale as " + Indexed("parts", j) +
                                          "; raise that part's max_instances instead");
      }
    }
    instances += part.max_instances > 0 ? part.max_instances : plan.options.max_instances;
    plan.parts.push_back(std::move(part));
  }
  if (instances > kMaxLocalizeTotalInstances) {
    return InvalidArgument("parts", "their max_instances add up to " + std::to_string(instances) + "; at most " +
                                        std::to_string(kMaxLocalizeTotalInstances));
  }
  return Status::Ok();
}

StatusOr<Pose3> RigidPose(const v1::Pose& pose, const std::string& field) {
  ASSIGN_OR_RETURN(const Pose3 parsed, PoseFromProto(pose, field));
  RETURN_IF_ERROR(CheckPosition(parsed.translation(), field + ".translation"));
  return parsed;
}

StatusOr<localization::PartSymmetries> ParseSymmetry(const v1::PartSymmetry& symmetry, const std::string& field) {
  localization::PartSymmetries out;
  if (symmetry.discrete_size() > 64) return InvalidArgument(field + ".discrete", "at most 64 transforms");
  if (symmetry.continuous_size() > 3) return InvalidArgument(field + ".continuous", "at most 3 axes");
  for (int j = 0; j < symmetry.discrete_size(); ++j) {
    ASSIGN_OR_RETURN(const Pose3 transform, RigidPose(symmetry.discrete(j), Indexed(field + ".discrete", j)));
    out.discrete.push_back(transform);
  }
  for (int j = 0; j < symmetry.continuous_size(); ++j) {
    const std::string axis_field = Indexed(field + ".continuous", j);
    const Eigen::Vector3d axis = FromProto(symmetry.continuous(j).axis());
    if (!axis.allFinite() || axis.norm() < 1e-9) return InvalidArgument(axis_field + ".axis", "must be a non-zero vector");
    const Eigen::Vector3d point = FromProto(symmetry.continuous(j).point());
    RETURN_IF_ERROR(CheckPosition(point, axis_field + ".point"));
    out.continuous.push_back({axis.normalized(), point});
  }
  return out;
}

StatusOr<uint32_t> PartIndex(uint32_t part, int parts, const std::string& field) {
  if (part >= static_cast<uint32_t>(parts)) {
    return InvalidArgument(field, "no part " + std::to_string(part) + " (" + std::to_string(parts) + " parts)");
  }
  return part;
}

Status CheckFraction(double value, double low, double high, bool low_open, const std::string& field) {
  const bool above_low = low_open ? value > low : value >= low;
  if (!std::isfinite(value) || !above_low || value > high) {
    return InvalidArgument(field, "must be within " + std::string(low_open ? "(" : "[") + std::to_string(low) + ", " +
                                      std::to_string(high) + "]");
  }
  return Status::Ok();
}

Status ParseScoringOptions(const v1::ScoringOptions& options, localization::ScoringOptions& out) {
  if (options.has_min_visible_fraction()) {
    RETURN_IF_ERROR(CheckFraction(options.min_visible_fraction(), 0, 1, false, "options.min_visible_fraction"));
    out.min_visible_fraction = options.min_visible_fraction();
  }
  if (options.has_add_threshold()) {
    RETURN_IF_ERROR(CheckFraction(options.add_threshold(), 0, 10, true, "options.add_threshold"));
    out.add_threshold = options.add_threshold();
  }
  if (options.mssd_thresholds_size() > 100) return InvalidArgument("options.mssd_thresholds", "at most 100 thresholds");
  for (int i = 0; i < options.mssd_thresholds_size(); ++i) {
    RETURN_IF_ERROR(CheckFraction(options.mssd_thresholds(i), 0, 10, true, Indexed("options.mssd_thresholds", i)));
    out.mssd_thresholds.push_back(options.mssd_thresholds(i));
  }
  out.keep_top_estimates = !options.keep_all_estimates();
  return Status::Ok();
}

}  // namespace

StatusOr<service::LocalizePlan> ParseLocalizeRequest(const v1::LocalizeRequest& request) {
  service::LocalizePlan plan;
  switch (request.source_case()) {
    case v1::LocalizeRequest::kCloudId:
      RETURN_IF_ERROR(RequireId(request.cloud_id(), "cloud_id"));
      plan.cloud_id = request.cloud_id();
      break;
    case v1::LocalizeRequest::kPoints:
      RETURN_IF_ERROR(ParseInlinePoints(request.points(), plan));
      break;
    case v1::LocalizeRequest::SOURCE_NOT_SET:
      return InvalidArgument("source", "required: cloud_id or points");
  }
  RETURN_IF_ERROR(ParseLocalizeOptions(request.options(), plan));
  RETURN_IF_ERROR(ParseLocalizeParts(request, plan));
  if (plan.normal_source == service::NormalSource::kCloud && request.has_points() && plan.normals.empty()) {
    return FailedPrecondition("options.normal_source", "NORMAL_SOURCE_CLOUD needs points.normals");
  }
  return plan;
}

StatusOr<service::ScoringPlan> ParseScorePosesRequest(const v1::ScorePosesRequest& request) {
  service::ScoringPlan plan;
  if (request.parts_size() == 0) return InvalidArgument("parts", "required (1 to 64 parts)");
  if (request.parts_size() > kMaxScoredParts) return InvalidArgument("parts", "at most 64 parts");
  if (request.truth_size() > kMaxScoredPoses) return InvalidArgument("truth", "at most 10000 poses");
  if (request.estimates_size() > kMaxScoredPoses) return InvalidArgument("estimates", "at most 10000 poses");
  for (int i = 0; i < request.parts_size(); ++i) {
    const v1::ScoredPart& part = request.parts(i);
    const std::string field = Indexed("parts", i);
    service::ScoringPart out;
    RETURN_IF_ERROR(RequireId(part.mesh_id(), field + ".mesh_id"));
    out.mesh_id = part.mesh_id();
    ASSIGN_OR_RETURN(out.scale, ScaleOrDefault(part.scale(), field + ".scale"));
    if (part.has_symmetry()) {
      ASSIGN_OR_RETURN(out.symmetries, ParseSymmetry(part.symmetry(), field + ".symmetry"));
    }
    plan.parts.push_back(std::move(out));
  }
  for (int i = 0; i < request.truth_size(); ++i) {
    const v1::TruePose& truth = request.truth(i);
    const std::string field = Indexed("truth", i);
    localization::TrueInstance out;
    ASSIGN_OR_RETURN(out.part_id, PartIndex(truth.part(), request.parts_size(), field + ".part"));
    ASSIGN_OR_RETURN(out.world_from_part, RigidPose(truth.world_from_part(), field + ".world_from_part"));
    if (truth.has_visible_fraction()) {
      // Measurement artefacts can put a few more points on an object than it gives alone (above 1);
      // such an object is fully visible.
      RETURN_IF_ERROR(CheckFraction(truth.visible_fraction(), 0, 1e3, false, field + ".visible_fraction"));
      out.visible_fraction = std::min(truth.visible_fraction(), 1.0);
    }
    plan.truth.push_back(out);
  }
  for (int i = 0; i < request.estimates_size(); ++i) {
    const v1::EstimatedPose& estimate = request.estimates(i);
    const std::string field = Indexed("estimates", i);
    localization::EstimatedInstance out;
    ASSIGN_OR_RETURN(out.part_id, PartIndex(estimate.part(), request.parts_size(), field + ".part"));
    ASSIGN_OR_RETURN(out.world_from_part, RigidPose(estimate.world_from_part(), field + ".world_from_part"));
    if (!std::isfinite(estimate.score())) return InvalidArgument(field + ".score", "must be finite");
    out.score = estimate.score();
    plan.estimates.push_back(out);
  }
  RETURN_IF_ERROR(ParseScoringOptions(request.options(), plan.options));
  ASSIGN_OR_RETURN(plan.grasp, ParseGraspScoring(request.has_gripper(), request.gripper(), request.grasp_options(),
                                                 request.has_up(), request.up()));
  return plan;
}

}  // namespace vscan::api
