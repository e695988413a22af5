#pragma once
// Next best views: of candidate sensor poses, the few that would see most of the true surface the
// scans missed. Each candidate is scanned virtually (rays cast against the true mesh through a
// thinned image of its camera); a missed ground-truth sample counts as seen when a hit lands within
// tau of it. Greedy: each pick adds the most samples not seen by the picks before it.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "evaluation/view_hits.h"
#include "sensor/camera.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::evaluation {

struct CandidateView {
  // Where the sensor would stand, in the frame of the mesh and samples.
  Pose3 frame_from_sensor = Pose3::Identity();
  // Caller's tag (e.g. an index into its list of viewpoints and table angles).
  uint32_t tag = 0;
};

struct NextBestViewOptions {
  size_t max_views = 3;
  // A sample is seen when a hit lands within tau of it (metres); > 0.
  double tau = 0.001;
  // Rays hitting the surface at more than this angle from its normal (degrees) see nothing.
  double max_incidence_deg = 80;
  // Each candidate's image is thinned so that it casts at most this many rays.
  size_t max_rays_per_view = 200'000;
  // Stop when the best candidate adds fewer samples than this.
  size_t min_gain_samples = 1;
  // Set: a candidate sees only the surface its own light would measure on the mesh's material
  // (neither dark nor saturated), as a scan with the returned light would.
  std::optional<MeasurableLight> light;
};

struct ViewPick {
  size_t candidate = 0;        // index into the candidates
  size_t gained_samples = 0;   // samples it adds to those covered before it
  double coverage_after = 0;   // share of all samples covered after it (and the picks before it)
};

// mesh and samples share one frame; covered[i] says whether samples[i] is covered already (same
// length). The camera is the sensor's (x right, y down, z forward). InvalidArgument names
// "next_best_views.<option>", "samples" or "covered"; Cancelled when cancel becomes true.
StatusOr<std::vector<ViewPick>> PickNextBestViews(const TriangleMesh& mesh, std::span<const Eigen::Vector3f> samples,
                                                  std::span<const uint8_t> covered,
                                                  const sensor::PinholeCamera& camera,
                                                  std::span<const CandidateView> candidates,
                                                  const NextBestViewOptions& options,
                                                  const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::evaluation
