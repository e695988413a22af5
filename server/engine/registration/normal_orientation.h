#pragma once
// One sign for the normals of a cloud without a viewpoint: Hoppe's propagation along a minimum
// spanning tree of the nearest-neighbour graph, then each connected part turned outward.

#include <span>

#include <Eigen/Core>

namespace vscan::registration {

// Flips normals in place so that neighbours agree, spreading first across the flattest edges of
// the graph that joins each point to its k nearest neighbours within max_distance. Each connected
// part then faces away from its centroid on (area-weighted) balance: outward for a closed surface
// and for most views of one. The rule depends only on the shape, not on the frame, so two scans of
// one surface get the same signs where they overlap. Normals must be finite and unit length.
void OrientNormalsConsistently(std::span<const Eigen::Vector3f> points, std::span<Eigen::Vector3f> normals, int k,
                               float max_distance);

}  // namespace vscan::registration
