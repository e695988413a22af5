#pragma once
// Localize: the baseline localizer on a stored cloud or on points a client sent, for one part (a
// stored mesh at a scale).

#include <atomic>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "localization/baseline_localizer.h"
#include "scenes/scene_registry.h"
#include "service/clouds/cloud_store.h"
#include "store/cloud_catalogue.h"
#include "vscan/common/status.h"

namespace vscan::service {

enum class NormalSource {
  kAuto,      // the cloud's estimated normals when it has them, else estimated here
  kEstimate,  // always estimated here, turned towards the viewpoint
  kCloud,     // the cloud's (true) normals, or the inline ones
};

// A request checked against the contract: either cloud_id or points (with normals empty or one
// per point).
struct LocalizePlan {
  std::string cloud_id;
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;
  std::string mesh_id;
  double scale = 1;
  localization::LocalizerOptions options;  // viewpoint filled in by RunLocalize when unset below
  NormalSource normal_source = NormalSource::kAuto;
  std::optional<Eigen::Vector3d> viewpoint;
};

struct LocalizeOutcome {
  localization::LocalizationResult result;
  store::CloudFrame frame = store::CloudFrame::kWorld;
  size_t points = 0;
  double localize_ms = 0;
};

// NOT_FOUND naming cloud_id or mesh_id; FAILED_PRECONDITION (normal_source) when kCloud is asked
// of points without normals; CANCELLED when cancel turns true.
StatusOr<LocalizeOutcome> RunLocalize(scenes::SceneRegistry& registry, const StoredClouds& clouds,
                                      const LocalizePlan& plan, const std::atomic<bool>* cancel);

}  // namespace vscan::service
