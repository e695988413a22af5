#pragma once
// Localize: the baseline localizer on a stored cloud or on points a client sent, for one or several
// parts (each a stored mesh at a scale) searched in one call.

#include <atomic>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "localization/baseline_localizer.h"
#include "localization/part_model_cache.h"
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

struct LocalizePartPlan {
  std::string mesh_id;
  double scale = 1;
  size_t max_instances = 0;          // 0: options.max_instances
  std::string field = "mesh_id";     // the request field that named the mesh, for NOT_FOUND
};

// A request checked against the contract: either cloud_id or points (with normals empty or one
// per point), and at least one part.
struct LocalizePlan {
  std::string cloud_id;
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;
  std::vector<LocalizePartPlan> parts;
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

// Every part's scaled mesh is loaded, then one search covers them all (the scan prepared once).
// NOT_FOUND naming cloud_id or the part's field (mesh_id, parts[1].mesh_id); FAILED_PRECONDITION
// (normal_source) when kCloud is asked of points without normals; CANCELLED when cancel turns
// true. progress, when set, is called on the calling thread between the search's stages. models,
// when given, keeps each part's model (by mesh id, scale and options) for the next call.
StatusOr<LocalizeOutcome> RunLocalize(scenes::SceneRegistry& registry, const StoredClouds& clouds,
                                      const LocalizePlan& plan, const std::atomic<bool>* cancel,
                                      const localization::LocalizeProgressCallback& progress = {},
                                      localization::PartModelCache* models = nullptr);

}  // namespace vscan::service
