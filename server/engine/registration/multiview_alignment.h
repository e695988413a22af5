#pragma once
// Many scans of one object into one frame: each new scan is aligned by ICP against the union of
// the scans aligned before it (so alignment can run while a campaign still scans), then a pose
// graph over every overlapping pair spreads the error so that it does not drift around the object
// (a full table revolution closes a loop).

#include <atomic>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "registration/point_to_plane_icp.h"
#include "registration/pose_graph.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::registration {

struct MultiviewOptions {
  // Scans are thinned to one point per voxel of this edge (metres) for alignment; > 0.
  double voxel_size = 0.002;
  // ICP settings; max_correspondence_distance <= 0 (the default here) means 5 voxels.
  IcpOptions icp = [] {
    IcpOptions o;
    o.max_correspondence_distance = 0;
    return o;
  }();
  // A scan whose fitness against the union stays below this is not aligned (and not merged).
  double min_fitness = 0.3;
  // A scan that alignment moves by more than this (metres, the RMS distance its points travel
  // from where the initial pose put them) is not aligned either: ICP only pairs points within the
  // correspondence distance, so a correction of many such distances means a start outside its
  // basin (a wrong initial pose) or a wrong minimum, whatever the fitness. <= 0 means 3 times the
  // correspondence distance.
  double max_correction = 0;
  // Run the pose graph in Finish.
  bool pose_graph = true;
  // Pairs whose thinned scans share less than this share of points (within the correspondence
  // distance and with normals within icp.max_normal_angle, at their current poses) get no
  // pose-graph edge.
  double min_pair_overlap = 0.2;
};

// One scan: points in its sensor frame and the pose alignment starts from.
struct ViewScan {
  std::vector<Eigen::Vector3f> points;  // sensor frame; non-finite points are ignored
  Pose3 initial_model_from_sensor = Pose3::Identity();
  // How firmly the initial pose is known, when it is (a robot's encoder noise): the information
  // (inverse covariance) over its right perturbation (w, t), as PoseGraphEdge weighs errors. The
  // pose graph then pulls the scan towards its initial pose as firmly, and no scan is held fixed.
  std::optional<Matrix6d> initial_information;
};

// fitness, inlier_rmse and iterations are those of the scan's ICP against the union when it was
// aligned (in Add, or in Finish's second try); the pose graph moves the pose but does not change
// them. The anchor has fitness 1 and no iterations.
struct ViewAlignment {
  Pose3 model_from_sensor = Pose3::Identity();
  bool aligned = false;
  std::string reason;  // why not aligned
  double fitness = 0;
  double inlier_rmse = 0;
  int iterations = 0;
};

class MultiviewAligner {
 public:
  // InvalidArgument names "alignment.voxel_size", "alignment.min_fitness" or an "icp." option.
  static StatusOr<MultiviewAligner> Create(const MultiviewOptions& options);
  MultiviewAligner(MultiviewAligner&&) noexcept;
  MultiviewAligner& operator=(MultiviewAligner&&) noexcept;
  ~MultiviewAligner();

  // Aligns one more scan. The first scan with enough points (100 after thinning) is the anchor: it
  // keeps its initial pose. A scan that cannot be aligned is reported with aligned = false and a
  // reason, and is not merged into the union. Cancelled when cancel becomes true; the scan is then
  // not added. InvalidArgument names "scan.initial_model_from_sensor" when it is not finite.
  StatusOr<ViewAlignment> Add(ViewScan scan, const std::atomic<bool>* cancel = nullptr);

  // The points aligned so far, thinned, in the model frame (e.g. for feature matching of a scan
  // whose pose is unknown).
  std::vector<Eigen::Vector3f> UnionPoints() const;
  // How many points (one per voxel) the union holds now.
  size_t UnionSize() const;

  // Tries once more each scan that was not aligned (against the whole union, which may now cover
  // it), runs the pose graph (when enabled) over the aligned scans, rebuilds the union at the final
  // poses and returns every scan's final alignment, in the order they were added. When cancelled,
  // the pose graph's poses are not applied (a scan the second try aligned stays aligned).
  StatusOr<std::vector<ViewAlignment>> Finish(const std::atomic<bool>* cancel = nullptr);

  size_t size() const;

 private:
  struct State;
  explicit MultiviewAligner(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace vscan::registration
