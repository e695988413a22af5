#pragma once
// What a reconstruction is measured with against the true surface, and the figures it gets.
//
// tau is a distance in metres. The reconstruction R is a point set (a mesh is sampled uniformly by
// area); the ground truth G is the true surface, sampled uniformly by area for the G -> R direction.
//   precision   = share of R's points within tau of G's surface (Tanks and Temples)
//   recall      = share of G's samples within tau of R (of R's points for a cloud, of R's surface for
//                 a mesh)
//   F-score     = 2 * precision * recall / (precision + recall), 0 when both are 0
//   accuracy    = mean and median distance R -> G (DTU); completeness = mean and median G -> R
//   Chamfer     = (accuracy mean + completeness mean) / 2
//   coverage    = recall of a scanned union; the G samples beyond tau are the uncovered regions.

#include <cstddef>
#include <cstdint>

#include "vscan/common/point_cloud.h"

namespace vscan::evaluation {

struct EvaluationOptions {
  // The F-score threshold, metres; > 0.
  double tau = 0.001;
  // Spacing of the surface samples (ground truth, and a reconstructed mesh); 0 means tau / 2.
  double sample_spacing = 0;
  // Upper bound on samples per surface, which caps memory for a large surface and a small tau.
  size_t max_samples = 4'000'000;
  uint64_t seed = 1;
};

struct DistanceStats {
  double mean = 0;
  double median = 0;
};

struct Evaluation {
  double tau = 0;
  double precision = 0;
  double recall = 0;
  double f_score = 0;
  DistanceStats accuracy;      // reconstruction -> ground truth
  DistanceStats completeness;  // ground truth -> reconstruction
  double chamfer = 0;
  size_t reconstruction_points = 0;
  size_t ground_truth_samples = 0;
  // Ground-truth samples farther than tau from the reconstruction (positions only).
  PointCloud uncovered;
};

double FScore(double precision, double recall);

}  // namespace vscan::evaluation
