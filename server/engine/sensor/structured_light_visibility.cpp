#include "sensor/structured_light_visibility.h"

#include <algorithm>
#include <cstdint>

#include "raycast/ray_queries.h"

namespace vscan::sensor {
namespace {

// Self-shadow margin at the surface end of a shadow segment, relative to its length and absolute.
constexpr float kRelativeMargin = 1e-4f;
constexpr float kMinMargin = 1e-5f;

}  // namespace

std::vector<ProjectorVisibility> ProjectorVisibilityOf(const raycast::RaycastScene& scene,
                                                       const Pose3& world_from_sensor, const StructuredLight& sl,
                                                       std::span<const Eigen::Vector3f> sensor_points) {
  std::vector<ProjectorVisibility> visibility(sensor_points.size(), ProjectorVisibility::kUnlit);
  const ProjectorField field(sl);
  const Eigen::Vector3f projector_world = (world_from_sensor * sl.projector_offset).cast<float>();

  std::vector<size_t> lit_candidates;
  std::vector<Eigen::Vector3f> from, to;
  for (size_t i = 0; i < sensor_points.size(); ++i) {
    const Eigen::Vector3d p = sensor_points[i].cast<double>();
    if (!p.allFinite() || !field.Contains(p)) continue;
    lit_candidates.push_back(i);
    from.push_back(projector_world);
    to.push_back((world_from_sensor * p).cast<float>());
  }
  // Each segment's own margin, so that far points do not widen the near ones'; OccludedSegments trims
  // it from both ends, which is harmless at the projector.
  const std::vector<uint8_t> occluded = raycast::OccludedSegments(scene, from, to, kRelativeMargin, kMinMargin);
  for (size_t k = 0; k < lit_candidates.size(); ++k) {
    visibility[lit_candidates[k]] = occluded[k] ? ProjectorVisibility::kShadowed : ProjectorVisibility::kLit;
  }
  return visibility;
}

}  // namespace vscan::sensor
