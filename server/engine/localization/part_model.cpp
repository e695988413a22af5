#include "localization/part_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "localization/boundary_points.h"
#include "localization/model_samples.h"

namespace vscan::localization {
namespace {

// The most part points the point-pair table is built over (it holds every ordered pair).
constexpr size_t kMaxPpfModelPoints = 3000;
constexpr double kVoxelsPerDiagonal = 50;
constexpr double kVoxelsPerMiddleExtent = 10;
constexpr double kMinPpfStepOfExtent = 0.04;
// Votes for poses within this many PPF steps and angle steps are pooled.
constexpr double kClusterDistanceInSteps = 2;
constexpr double kClusterAngleInSteps = 2.5;
constexpr uint64_t kSampleSeed = 1;

}  // namespace

size_t PartModel::MemoryBytes() const {
  const size_t points = model.points.size() + ppf_points.points.size();
  return (ppf ? ppf->memory_bytes() : 0) + points * 2 * sizeof(Eigen::Vector3f) + model.points.size() * 32;
}

double DefaultVoxel(const TriangleMesh& part) {
  Eigen::Vector3f lo, hi;
  part.Bounds(lo, hi);
  Eigen::Vector3f extents = hi - lo;
  std::sort(extents.data(), extents.data() + 3);
  return std::min(static_cast<double>(extents.norm()) / kVoxelsPerDiagonal,
                  static_cast<double>(extents[1]) / kVoxelsPerMiddleExtent);
}

StatusOr<PartModel> BuildPartModel(const TriangleMesh& part, const std::string& field, const PartModelSettings& settings) {
  const ModelSamples samples = SampleModel(part, settings.samples, kSampleSeed);
  if (samples.points.empty()) return InvalidArgument(field, "has no surface");
  PartModel m;
  m.voxel = settings.voxel_size > 0 ? settings.voxel_size : DefaultVoxel(part);
  m.ppf_step = settings.ppf_step_voxels * m.voxel;
  Eigen::Vector3f lo, hi;
  part.Bounds(lo, hi);
  m.bounds = Eigen::AlignedBox3f(lo, hi);
  m.extent = static_cast<double>((hi - lo).norm());
  // A long thin part's fine voxel would make its pair step a small share of its length, and the
  // pairs a scan point votes with grow with the square of that ratio.
  if (settings.voxel_size == 0) m.ppf_step = std::max(m.ppf_step, kMinPpfStepOfExtent * m.extent);
  const OrientedPoints all{samples.points, samples.normals};
  m.model = ThinOriented(all, m.voxel, kFaceSplitAngleRad);
  m.ppf_points = ThinOriented(all, m.ppf_step, kFaceSplitAngleRad);
  // The pair table grows with the square of these points: 3000 make 9 million pairs (144 MiB). A
  // voxel of the localizer's own choosing (a long thin part's) coarsens the table's step to fit.
  while (settings.voxel_size == 0 && m.ppf_points.points.size() > kMaxPpfModelPoints) {
    m.ppf_step *= 1.05 * std::sqrt(static_cast<double>(m.ppf_points.points.size()) / kMaxPpfModelPoints);
    m.ppf_points = ThinOriented(all, m.ppf_step, kFaceSplitAngleRad);
  }
  if (m.ppf_points.points.size() > kMaxPpfModelPoints) {
    return ResourceExhausted("options.voxel_size",
                             "a voxel of " + std::to_string(m.voxel * 1e3) + " mm leaves " +
                                 std::to_string(m.ppf_points.points.size()) +
                                 " points on the part for its pair table, more than the " +
                                 std::to_string(kMaxPpfModelPoints) +
                                 " it may hold; use a larger voxel (0 picks one from the part's size)");
  }
  m.model_tree = std::make_unique<spatial::KdTree>(m.model.points);
  m.icp_target = std::make_unique<registration::TargetIndex>(m.model.points, m.model.normals);
  PpfSettings ppf;
  ppf.distance_step = m.ppf_step;
  ppf.angle_step_rad = settings.angle_step_rad;
  ppf.scene_reference_stride = settings.scene_reference_stride;
  ppf.cluster_distance = kClusterDistanceInSteps * m.ppf_step;
  ppf.cluster_angle_rad = kClusterAngleInSteps * ppf.angle_step_rad;
  m.ppf_rims = RimDirections(m.ppf_points, kRimRadiusInPpfSteps * m.ppf_step);
  m.ppf = std::make_unique<PpfModel>(m.ppf_points.points, m.ppf_points.normals, m.ppf_rims, ppf);
  return m;
}

}  // namespace vscan::localization
