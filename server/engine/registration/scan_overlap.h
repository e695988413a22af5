#pragma once
// Which clouds overlap: cheap candidates from the coarse cells they share, then the measured share
// of one cloud's points that lie within reach of the other.

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "registration/target_index.h"

namespace vscan::registration {

// For each cloud, the (at most per_cloud) others that share the most cells of edge cell_size with
// it, ties to the lower index, none sharing no cell. The union of these as pairs (a < b), sorted.
std::vector<std::pair<size_t, size_t>> CandidatePairs(std::span<const std::vector<Eigen::Vector3f>> clouds,
                                                      double cell_size, size_t per_cloud);

// The share of source points (an even subset of at most max_samples of them) whose nearest target
// point lies within reach and has a normal within max_normal_angle (radians, sign ignored) of
// theirs, so that the far side of a thin part does not count as the same surface; 0 for an empty
// source. Source points and normals are in the target's frame.
double OverlapShare(std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> source_normals,
                    const TargetIndex& target, double reach, double max_normal_angle, size_t max_samples);

}  // namespace vscan::registration
