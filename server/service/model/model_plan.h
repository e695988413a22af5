#pragma once
// A model job's request checked against what the server holds and turned into a plan: the clouds
// resolved in order, the options with their defaults, the scene that holds the ground truth and the
// mount that places next best views. Errors name the request's fields ("cloud_ids[3]",
// "alignment.voxel_size"); the api layer puts them under "spec".

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "capture/returned_light.h"
#include "service/model/campaign_records.h"
#include "service/context/service_context.h"
#include "store/catalogue.h"
#include "store/cloud_catalogue.h"
#include "vscan/common/pose.h"

namespace vscan::service {

inline constexpr size_t kMaxModelClouds = 1000;
inline constexpr uint64_t kMaxModelPoints = 60'000'000;
inline constexpr uint32_t kMaxNextBestViews = 20;
inline constexpr uint32_t kDefaultNextBestViews = 3;
inline constexpr double kDefaultMinFitness = 0.3;
inline constexpr uint32_t kDefaultPoissonDepth = 8;
// PCL's solver cannot be stopped midway: the depth bounds how long a stop waits for it.
inline constexpr uint32_t kMaxPoissonDepth = 10;
// Largest voxel, correspondence distance or tau a request may give, metres.
inline constexpr double kMaxModelLength = 1.0;

enum class InitialPoseMode { kAuto, kKnown, kFeatures };
enum class ReconstructionKind { kAuto, kTsdf, kPoisson };

// An axis-aligned box in the model frame.
struct ModelBox {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
};

// What a client asks for, as the api layer read it (unchecked beyond presence and id syntax).
struct ModelRequest {
  std::vector<std::string> cloud_ids;
  std::string campaign_job_id;
  bool skip_alignment = false;
  InitialPoseMode initial_pose = InitialPoseMode::kAuto;
  double voxel_size = 0;
  double max_correspondence_distance = 0;
  double min_fitness = 0;
  bool skip_pose_graph = false;
  bool reconstruct = false;
  ReconstructionKind reconstruction = ReconstructionKind::kAuto;
  double reconstruction_voxel_size = 0;
  uint32_t poisson_depth = 0;
  bool evaluate = false;
  double tau = 0;
  uint32_t next_best_views = 0;
  bool skip_next_best_views = false;
  std::string scene_id;
  std::string mount_id;
  std::optional<ModelBox> crop;
  std::string name;
};

// One cloud of the job, with what the plan learnt about it.
struct ModelCloud {
  store::CloudRecord record;
  // How messages name it: "cloud_ids[3]" or the campaign's scan name.
  std::string label;
  // The table of the scene it was scanned in, when that scene has one.
  std::optional<store::TableRecord> table;
  // Where the arm was told to put the sensor (world frame), for a campaign's scan.
  std::optional<Pose3> commanded_world_from_sensor;
  // How firmly that pose is known (the arm's encoder noise), as information over its right
  // perturbation (w, t); the pose graph weighs it.
  std::optional<Eigen::Matrix<double, 6, 6>> initial_information;
};

struct ModelPlan {
  std::string name;
  std::vector<ModelCloud> clouds;
  uint64_t total_points = 0;

  bool align = true;
  InitialPoseMode initial_pose = InitialPoseMode::kAuto;
  double voxel_size = 0;                   // 0: from the object's size
  double max_correspondence_distance = 0;  // 0: from the voxel size
  double min_fitness = kDefaultMinFitness;
  bool pose_graph = true;

  bool reconstruct = false;
  // kAuto is resolved here: kTsdf when every cloud has a camera and pixel coordinates.
  ReconstructionKind reconstruction = ReconstructionKind::kPoisson;
  double reconstruction_voxel_size = 0;  // 0: from the object's size
  uint32_t poisson_depth = kDefaultPoissonDepth;

  bool evaluate = false;
  double tau = 0;  // 0: 1/200 of the ground truth's bounding-box diagonal
  uint32_t next_best_views = kDefaultNextBestViews;  // 0 when skipped
  // The scene that holds the ground truth and the mount that places the sensor (empty: none).
  std::optional<store::SceneRecord> scene;
  std::string mount_id;
  // Why no next best views will be proposed although evaluation runs (no mount, ...).
  std::string next_best_views_note;
  // The crop the request gave; without it the run uses the default about the ground truth.
  std::optional<ModelBox> crop;
  // The returned light the scans were taken under (the campaign's): next best views then count
  // only the surface that light would measure on the object's material.
  std::optional<capture::ReturnedLightSpec> returned_light;
};

// Checks the request and resolves it. INVALID_ARGUMENT for a value out of range, NOT_FOUND for an
// unknown cloud, job, scene or mount, FAILED_PRECONDITION for what the data cannot give (evaluation
// without a scene, TSDF without cameras, a campaign still running). campaigns reads what campaigns
// stored about their scans.
StatusOr<ModelPlan> PlanModel(ServiceContext& context, CampaignRecords& campaigns, const ModelRequest& request);

// Every cloud a job stored (a campaign's scans).
StatusOr<std::vector<store::CloudRecord>> ListJobClouds(ServiceContext& context, const std::string& job_id);

// The checks that need nothing but the request (a dry run may call them on their own).
Status CheckModelOptions(const ModelRequest& request);

// The same without the clouds: the options alone.
Status CheckModelSettings(const ModelRequest& request);

// The model stages a campaign runs on its own scans, which it adds to plan.clouds as it captures
// them: the request's options (its clouds are ignored), the campaign's scene and mount. TSDF is
// possible when scans_have_pixels. An empty scene_id (a dry run) checks the options alone.
StatusOr<ModelPlan> PlanCampaignModel(ServiceContext& context, const ModelRequest& request,
                                      const std::string& scene_id, const std::string& mount_id,
                                      bool scans_have_pixels);

}  // namespace vscan::service
