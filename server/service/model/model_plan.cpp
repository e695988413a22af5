#include "service/model/model_plan.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "service/model/pose_prior.h"
#include "service/scan/request_memory.h"
#include "vscan/common/physical_limits.h"
#include "vscan/common/point_cloud.h"
#include "service/job/message_numbers.h"
#include "service/job/job_kind.h"

namespace vscan::service {
namespace {

// Smallest non-zero voxel a request may give: finer ones would take more memory than they are worth.
constexpr double kMinAlignmentVoxel = 1e-4;
constexpr double kMinReconstructionVoxel = 2e-4;
constexpr double kMinTau = 1e-5;
constexpr int kCloudListPage = 500;

std::string Index(const char* field, size_t i) { return std::string(field) + "[" + std::to_string(i) + "]"; }

// 0 (pick it) or a length in [min, kMaxModelLength] metres.
Status CheckLength(double value, const char* field, double min) {
  if (value == 0) return Status::Ok();
  if (!std::isfinite(value) || value < min || value > kMaxModelLength) {
    return InvalidArgument(field, "must be 0 (pick it) or a length in [" + Number(min) + ", " +
                                      Number(kMaxModelLength) + "] metres, not " + Number(value));
  }
  return Status::Ok();
}

Status CheckCorner(const Eigen::Vector3d& p, const char* field) {
  if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinateM) {
    return InvalidArgument(field, "coordinates must be finite and within " + Number(kMaxCoordinateM) + " m");
  }
  return Status::Ok();
}

Status CheckCrop(const ModelBox& crop) {
  RETURN_IF_ERROR(CheckCorner(crop.min, "crop.min"));
  RETURN_IF_ERROR(CheckCorner(crop.max, "crop.max"));
  if (!(crop.min.array() < crop.max.array()).all()) {
    return InvalidArgument("crop", "min must be below max on every axis");
  }
  return Status::Ok();
}

const char* StateText(store::JobState state) {
  switch (state) {
    case store::JobState::kQueued: return "queued";
    case store::JobState::kRunning: return "running";
    case store::JobState::kSucceeded: return "succeeded";
    case store::JobState::kFailed: return "failed";
    case store::JobState::kCancelled: return "cancelled";
    case store::JobState::kInterrupted: return "interrupted";
  }
  return "unknown";
}

std::string Describe(const store::CloudRecord& cloud) { return "cloud '" + cloud.cloud_id + "' (" + cloud.name + ")"; }

// Reads campaigns once each.
class CampaignCache {
 public:
  explicit CampaignCache(CampaignRecords& records) : records_(records) {}

  StatusOr<const CampaignRecord*> Get(const std::string& job_id) {
    auto it = cache_.find(job_id);
    if (it == cache_.end()) {
      ASSIGN_OR_RETURN(CampaignRecord record, records_.Get(job_id));
      it = cache_.emplace(job_id, std::move(record)).first;
    }
    return &it->second;
  }

 private:
  CampaignRecords& records_;
  std::map<std::string, CampaignRecord> cache_;
};

// Where the campaign told the arm to put the sensor for this scan, and how firmly the arm knew it
// (while its mount exists).
void SetCommandedPose(ServiceContext& context, const CampaignRecord& campaign, ModelCloud& cloud) {
  for (const CampaignScanRecord& scan : campaign.scans) {
    if (scan.name != cloud.record.name) continue;
    cloud.commanded_world_from_sensor = scan.commanded_world_from_sensor;
    if (!scan.commanded_world_from_sensor || scan.commanded_joints.size() == 0) return;
    auto mounted = context.robots.Mount(campaign.mount_id);
    if (!mounted.ok()) return;
    auto information = CommandedPoseInformation(*mounted, scan.commanded_joints, campaign.encoder_noise);
    if (information.ok()) cloud.initial_information = *information;
    return;
  }
}

StatusOr<std::vector<ModelCloud>> CloudsById(ServiceContext& context, CampaignCache& campaigns,
                                             const std::vector<std::string>& ids) {
  std::vector<ModelCloud> clouds;
  for (size_t i = 0; i < ids.size(); ++i) {
    ModelCloud cloud;
    cloud.label = Index("cloud_ids", i);
    auto record = context.clouds.Get(ids[i]);
    if (!record.ok()) {
      if (record.status().code() == StatusCode::kNotFound) {
        return NotFound(cloud.label, "cloud '" + ids[i] + "' not found");
      }
      return record.status();
    }
    cloud.record = std::move(record).value();
    if (cloud.record.origin == store::CloudOrigin::kCampaignScan && !cloud.record.job_id.empty()) {
      auto campaign = campaigns.Get(cloud.record.job_id);
      if (campaign.ok()) {
        SetCommandedPose(context, **campaign, cloud);
      } else if (campaign.status().code() != StatusCode::kNotFound) {
        return campaign.status();
      }
    }
    clouds.push_back(std::move(cloud));
  }
  return clouds;
}

StatusOr<std::vector<ModelCloud>> CampaignClouds(ServiceContext& context, CampaignCache& campaigns,
                                                 const std::string& job_id) {
  constexpr const char* kField = "campaign_job_id";
  auto found = campaigns.Get(job_id);
  if (!found.ok()) {
    if (found.status().code() == StatusCode::kNotFound) return NotFound(kField, "job '" + job_id + "' not found");
    return found.status();
  }
  const CampaignRecord& campaign = **found;
  if (campaign.kind != JobKindName(JobKind::kCampaign)) {
    return InvalidArgument(kField, "job '" + job_id + "' is a " + campaign.kind + " job, not a campaign");
  }
  if (campaign.state == store::JobState::kQueued || campaign.state == store::JobState::kRunning) {
    return FailedPrecondition(kField, "campaign '" + job_id + "' is still " + StateText(campaign.state) +
                                          "; start the model job when it has ended");
  }
  ASSIGN_OR_RETURN(std::vector<store::CloudRecord> records, ListJobClouds(context, job_id));
  if (records.empty()) return FailedPrecondition(kField, "campaign '" + job_id + "' captured no scans");
  // Capture order, as the campaign recorded its scans; names it does not list go last.
  std::map<std::string, size_t> order;
  for (size_t i = 0; i < campaign.scans.size(); ++i) order.emplace(campaign.scans[i].name, i);
  auto rank = [&](const store::CloudRecord& r) {
    const auto it = order.find(r.name);
    return std::make_pair(it == order.end() ? order.size() : it->second, r.name);
  };
  std::stable_sort(records.begin(), records.end(),
                   [&](const store::CloudRecord& a, const store::CloudRecord& b) { return rank(a) < rank(b); });
  std::vector<ModelCloud> clouds;
  for (store::CloudRecord& record : records) {
    ModelCloud cloud;
    cloud.label = kField;
    cloud.record = std::move(record);
    SetCommandedPose(context, campaign, cloud);
    clouds.push_back(std::move(cloud));
  }
  return clouds;
}

StatusOr<std::optional<store::SceneRecord>> FindScene(ServiceContext& context, const std::string& scene_id) {
  auto scene = context.registry.catalogue().GetScene(scene_id);
  if (scene.ok()) return std::optional<store::SceneRecord>(std::move(scene).value());
  if (scene.status().code() == StatusCode::kNotFound) return std::optional<store::SceneRecord>();
  return scene.status();
}

// Each cloud's table: the model frame undoes its angle about that table's axis.
Status ResolveTables(ServiceContext& context, std::vector<ModelCloud>& clouds) {
  std::map<std::string, std::optional<store::SceneRecord>> scenes;
  for (ModelCloud& cloud : clouds) {
    const std::string& id = cloud.record.scene_id;
    if (id.empty()) continue;
    auto it = scenes.find(id);
    if (it == scenes.end()) {
      ASSIGN_OR_RETURN(auto scene, FindScene(context, id));
      it = scenes.emplace(id, std::move(scene)).first;
    }
    const double angle = cloud.record.table_angle_deg.value_or(0.0);
    if (!it->second) {
      if (angle != 0.0) {
        return FailedPrecondition(cloud.label, Describe(cloud.record) + " was scanned at table angle " +
                                                   Number(angle) + " deg in scene '" + id +
                                                   "', which no longer exists, so that turn cannot be undone");
      }
      continue;
    }
    if (it->second->table.enabled) cloud.table = it->second->table;
  }
  return Status::Ok();
}

bool HasKnownPose(const ModelCloud& cloud) {
  return cloud.commanded_world_from_sensor.has_value() || cloud.record.world_from_sensor.has_value();
}

bool CanFuse(const store::CloudRecord& cloud) {
  return cloud.camera.has_value() && (cloud.fields & kFieldPixel) != 0;
}

Status CheckPoses(const ModelRequest& request, const std::vector<ModelCloud>& clouds) {
  for (const ModelCloud& cloud : clouds) {
    if (request.skip_alignment && !cloud.record.world_from_sensor &&
        cloud.record.frame == store::CloudFrame::kSensor) {
      return FailedPrecondition(cloud.label, Describe(cloud.record) +
                                                 " is in its sensor frame without a sensor pose: it cannot be "
                                                 "placed with skip_alignment");
    }
    if (!request.skip_alignment && request.initial_pose == InitialPoseMode::kKnown && !HasKnownPose(cloud)) {
      return FailedPrecondition(cloud.label, Describe(cloud.record) +
                                                 " has no known sensor pose; use INITIAL_POSE_FEATURES");
    }
  }
  return Status::Ok();
}

StatusOr<ReconstructionKind> ResolveReconstruction(const ModelRequest& request, const std::vector<ModelCloud>& clouds) {
  const auto lacking = std::find_if(clouds.begin(), clouds.end(), [](const ModelCloud& c) { return !CanFuse(c.record); });
  switch (request.reconstruction) {
    case ReconstructionKind::kPoisson: return ReconstructionKind::kPoisson;
    case ReconstructionKind::kAuto:
      return lacking == clouds.end() ? ReconstructionKind::kTsdf : ReconstructionKind::kPoisson;
    case ReconstructionKind::kTsdf: break;
  }
  if (lacking != clouds.end()) {
    return FailedPrecondition("reconstruction.method",
                              "TSDF needs every cloud's camera and pixel field; " + Describe(lacking->record) +
                                  (lacking->record.camera ? " has no pixel field" : " has no camera"));
  }
  if (request.skip_alignment) {
    for (const ModelCloud& cloud : clouds) {
      if (!cloud.record.world_from_sensor) {
        return FailedPrecondition("reconstruction.method", "TSDF with skip_alignment needs every cloud's sensor pose; " +
                                                               Describe(cloud.record) + " has none");
      }
    }
  }
  return ReconstructionKind::kTsdf;
}

// The scene the request names, else the one every cloud (or the campaign) names.
StatusOr<std::optional<store::SceneRecord>> ResolveScene(ServiceContext& context, const ModelRequest& request,
                                                         const std::vector<ModelCloud>& clouds) {
  if (!request.scene_id.empty()) {
    ASSIGN_OR_RETURN(auto scene, FindScene(context, request.scene_id));
    if (!scene) return NotFound("scene_id", "no scene '" + request.scene_id + "'");
    return scene;
  }
  std::set<std::string> ids;
  for (const ModelCloud& cloud : clouds) {
    if (!cloud.record.scene_id.empty()) ids.insert(cloud.record.scene_id);
  }
  if (ids.size() > 1 && request.evaluate) {
    return InvalidArgument("scene_id", "the clouds come from " + std::to_string(ids.size()) +
                                           " scenes; name the one that holds the ground truth");
  }
  if (ids.size() != 1) return std::optional<store::SceneRecord>();
  return FindScene(context, *ids.begin());
}

// The returned light of the one campaign every cloud comes from, when it asked for one.
std::optional<capture::ReturnedLightSpec> CampaignLight(CampaignCache& campaigns, const std::vector<ModelCloud>& clouds) {
  std::set<std::string> jobs;
  for (const ModelCloud& cloud : clouds) jobs.insert(cloud.record.job_id);
  if (jobs.size() != 1 || jobs.begin()->empty()) return std::nullopt;
  auto campaign = campaigns.Get(*jobs.begin());
  if (!campaign.ok()) return std::nullopt;
  return (*campaign)->returned_light;
}

// The mount the request names, else the campaign's when all clouds come from one campaign.
StatusOr<std::string> ResolveMount(ServiceContext& context, CampaignCache& campaigns, const ModelRequest& request,
                                   const std::vector<ModelCloud>& clouds,
                                   const std::optional<store::SceneRecord>& scene) {
  if (!request.mount_id.empty()) {
    ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, context.robots.Mount(request.mount_id));
    if (scene && mounted.mount.scene_id != scene->scene_id) {
      return FailedPrecondition("mount_id", "mount '" + request.mount_id + "' stands in scene '" +
                                                mounted.mount.scene_id + "', not in '" + scene->scene_id + "'");
    }
    return request.mount_id;
  }
  std::set<std::string> jobs;
  for (const ModelCloud& cloud : clouds) jobs.insert(cloud.record.job_id);
  if (jobs.size() != 1 || jobs.begin()->empty()) return std::string();
  auto campaign = campaigns.Get(*jobs.begin());
  if (!campaign.ok() || (*campaign)->mount_id.empty()) return std::string();
  auto mounted = context.robots.Mount((*campaign)->mount_id);
  if (!mounted.ok() || (scene && mounted->mount.scene_id != scene->scene_id)) return std::string();
  return (*campaign)->mount_id;
}

void ApplyOptions(const ModelRequest& request, ModelPlan& plan) {
  plan.align = !request.skip_alignment;
  plan.initial_pose = request.initial_pose;
  plan.voxel_size = request.voxel_size;
  plan.max_correspondence_distance = request.max_correspondence_distance;
  plan.min_fitness = request.min_fitness == 0 ? kDefaultMinFitness : request.min_fitness;
  plan.pose_graph = !request.skip_pose_graph;
  plan.reconstruct = request.reconstruct;
  plan.reconstruction_voxel_size = request.reconstruction_voxel_size;
  plan.poisson_depth = request.poisson_depth == 0 ? kDefaultPoissonDepth : request.poisson_depth;
  plan.evaluate = request.evaluate;
  plan.tau = request.tau;
  plan.crop = request.crop;
}

Status CheckEvaluationScene(const ModelPlan& plan) {
  if (plan.evaluate && !plan.scene) {
    return FailedPrecondition("scene_id", "evaluation needs the scene that holds the true objects; the clouds name none");
  }
  if (plan.evaluate && plan.scene->objects.empty()) {
    return FailedPrecondition("scene_id", "scene '" + plan.scene->scene_id + "' holds no objects to evaluate against");
  }
  return Status::Ok();
}

void ResolveNextBestViews(const ModelRequest& request, ModelPlan& plan) {
  plan.next_best_views = 0;
  if (!plan.evaluate || request.skip_next_best_views) return;
  if (plan.mount_id.empty()) {
    plan.next_best_views_note = "no robot mount to place the sensor: give mount_id";
  } else {
    plan.next_best_views = request.next_best_views == 0 ? kDefaultNextBestViews : request.next_best_views;
  }
}

}  // namespace

StatusOr<std::vector<store::CloudRecord>> ListJobClouds(ServiceContext& context, const std::string& job_id) {
  std::vector<store::CloudRecord> records;
  std::string after;
  for (;;) {
    ASSIGN_OR_RETURN(auto page, context.clouds.List(after, kCloudListPage, job_id));
    records.insert(records.end(), page.begin(), page.end());
    if (static_cast<int>(page.size()) < kCloudListPage) break;
    after = page.back().cloud_id;
  }
  return records;
}

Status CheckModelOptions(const ModelRequest& request) {
  if (request.cloud_ids.empty() && request.campaign_job_id.empty()) {
    return InvalidArgument("cloud_ids", "give the clouds to model, or campaign_job_id");
  }
  if (!request.cloud_ids.empty() && !request.campaign_job_id.empty()) {
    return InvalidArgument("campaign_job_id", "give cloud_ids or campaign_job_id, not both");
  }
  if (request.cloud_ids.size() > kMaxModelClouds) {
    return InvalidArgument("cloud_ids", "at most " + std::to_string(kMaxModelClouds) + " clouds, not " +
                                            std::to_string(request.cloud_ids.size()));
  }
  std::map<std::string, size_t> seen;
  for (size_t i = 0; i < request.cloud_ids.size(); ++i) {
    const auto [it, inserted] = seen.emplace(request.cloud_ids[i], i);
    if (!inserted) return InvalidArgument(Index("cloud_ids", i), "repeats " + Index("cloud_ids", it->second));
  }
  return CheckModelSettings(request);
}

Status CheckModelSettings(const ModelRequest& request) {
  RETURN_IF_ERROR(CheckLength(request.voxel_size, "alignment.voxel_size", kMinAlignmentVoxel));
  RETURN_IF_ERROR(
      CheckLength(request.max_correspondence_distance, "alignment.max_correspondence_distance", kMinAlignmentVoxel));
  if (!std::isfinite(request.min_fitness) || request.min_fitness < 0 || request.min_fitness > 1) {
    return InvalidArgument("alignment.min_fitness", "must be in [0, 1] (0: " + Number(kDefaultMinFitness) + ")");
  }
  RETURN_IF_ERROR(CheckLength(request.reconstruction_voxel_size, "reconstruction.voxel_size", kMinReconstructionVoxel));
  if (request.poisson_depth > kMaxPoissonDepth) {
    return InvalidArgument("reconstruction.poisson_depth", "at most " + std::to_string(kMaxPoissonDepth));
  }
  RETURN_IF_ERROR(CheckLength(request.tau, "evaluation.tau", kMinTau));
  if (request.next_best_views > kMaxNextBestViews) {
    return InvalidArgument("evaluation.next_best_views", "at most " + std::to_string(kMaxNextBestViews));
  }
  if (request.crop) RETURN_IF_ERROR(CheckCrop(*request.crop));
  return Status::Ok();
}

StatusOr<ModelPlan> PlanModel(ServiceContext& context, CampaignRecords& campaign_records, const ModelRequest& request) {
  RETURN_IF_ERROR(CheckModelOptions(request));
  CampaignCache campaigns(campaign_records);
  ModelPlan plan;
  plan.name = request.name;
  if (request.campaign_job_id.empty()) {
    ASSIGN_OR_RETURN(plan.clouds, CloudsById(context, campaigns, request.cloud_ids));
  } else {
    ASSIGN_OR_RETURN(plan.clouds, CampaignClouds(context, campaigns, request.campaign_job_id));
    if (plan.clouds.size() > kMaxModelClouds) {
      return InvalidArgument("campaign_job_id", "the campaign holds " + std::to_string(plan.clouds.size()) +
                                                    " scans, more than the " + std::to_string(kMaxModelClouds) +
                                                    " a model job takes; list cloud_ids instead");
    }
  }
  for (const ModelCloud& cloud : plan.clouds) plan.total_points += cloud.record.points;
  if (plan.total_points > kMaxModelPoints) {
    return ResourceExhausted(request.campaign_job_id.empty() ? "cloud_ids" : "campaign_job_id",
                             "the clouds hold " + std::to_string(plan.total_points) + " points, more than the " +
                                 std::to_string(kMaxModelPoints) + " a model job takes");
  }
  // Each point is held as read, as placed, with its normal, in the union and its k-d tree.
  constexpr uint64_t kHeldBytesPerPoint = 96;
  RETURN_IF_ERROR(CheckRequestMemory(plan.total_points * kHeldBytesPerPoint, context.options.limits,
                                     request.campaign_job_id.empty() ? "cloud_ids" : "campaign_job_id",
                                     "aligning " + std::to_string(plan.total_points) + " points"));
  RETURN_IF_ERROR(ResolveTables(context, plan.clouds));
  RETURN_IF_ERROR(CheckPoses(request, plan.clouds));

  ApplyOptions(request, plan);
  if (plan.reconstruct) {
    ASSIGN_OR_RETURN(plan.reconstruction, ResolveReconstruction(request, plan.clouds));
  }
  if (plan.reconstruct && plan.reconstruction == ReconstructionKind::kTsdf) {
    // Fusion holds every cloud's depth and weight images (4 + 4 bytes a pixel) beside the points.
    uint64_t pixels = 0;
    for (const ModelCloud& cloud : plan.clouds) {
      if (cloud.record.camera) pixels += uint64_t{cloud.record.camera->width} * cloud.record.camera->height;
    }
    RETURN_IF_ERROR(CheckRequestMemory(plan.total_points * kHeldBytesPerPoint + pixels * 8, context.options.limits,
                                       "reconstruction.method",
                                       "fusing " + std::to_string(plan.clouds.size()) + " depth images of " +
                                           std::to_string(pixels) + " pixels in all"));
  }
  ASSIGN_OR_RETURN(plan.scene, ResolveScene(context, request, plan.clouds));
  RETURN_IF_ERROR(CheckEvaluationScene(plan));
  ASSIGN_OR_RETURN(plan.mount_id, ResolveMount(context, campaigns, request, plan.clouds, plan.scene));
  plan.returned_light = CampaignLight(campaigns, plan.clouds);
  ResolveNextBestViews(request, plan);
  return plan;
}

StatusOr<ModelPlan> PlanCampaignModel(ServiceContext& context, const ModelRequest& request,
                                      const std::string& scene_id, const std::string& mount_id,
                                      bool scans_have_pixels) {
  RETURN_IF_ERROR(CheckModelSettings(request));
  ModelPlan plan;
  plan.name = request.name;
  ApplyOptions(request, plan);
  if (plan.reconstruct) {
    if (request.reconstruction == ReconstructionKind::kTsdf && !scans_have_pixels) {
      return FailedPrecondition("reconstruction.method", "TSDF needs the scans' pixel field; add it to fields");
    }
    const bool tsdf = request.reconstruction == ReconstructionKind::kTsdf ||
                      (request.reconstruction == ReconstructionKind::kAuto && scans_have_pixels);
    plan.reconstruction = tsdf ? ReconstructionKind::kTsdf : ReconstructionKind::kPoisson;
  }
  // A dry run without a scene checks the options alone.
  if (scene_id.empty()) return plan;
  ASSIGN_OR_RETURN(plan.scene, FindScene(context, scene_id));
  RETURN_IF_ERROR(CheckEvaluationScene(plan));
  plan.mount_id = mount_id;
  ResolveNextBestViews(request, plan);
  return plan;
}

}  // namespace vscan::service
