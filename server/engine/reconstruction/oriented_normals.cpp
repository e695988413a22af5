#include "reconstruction/oriented_normals.h"

#include "normals/normal_estimation.h"

namespace vscan::reconstruction {

StatusOr<OrientedCloud> OrientNormals(std::span<const Eigen::Vector3f> positions,
                                      std::span<const Eigen::Vector3f> view_directions, int k) {
  if (positions.size() != view_directions.size()) {
    return InvalidArgument("view_directions: one per position is needed");
  }
  normals::NormalOptions options;
  options.k = k;
  options.orient_towards_viewpoint = false;
  ASSIGN_OR_RETURN(std::vector<Eigen::Vector3f> normals, normals::EstimateNormals(positions, options));
  OrientedCloud out;
  out.positions.reserve(positions.size());
  out.normals.reserve(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    if (!normals[i].allFinite()) continue;
    out.positions.push_back(positions[i]);
    out.normals.push_back(normals[i].dot(view_directions[i]) < 0 ? -normals[i] : normals[i]);
  }
  return out;
}

}  // namespace vscan::reconstruction
