#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "grasping/grasp_kinds.h"
#include "grasping/suction_seal.h"

namespace vscan::grasping {

std::vector<Grasp> SuctionGrasps(const SurfaceSamples& dense, const SurfaceSamples& candidates,
                                 const SuctionCup& cup, const GraspOptions& options) {
  const double spacing = std::sqrt(dense.area / double(dense.points.size()));
  const DiscCells disc = DiscCellsFor(dense, cup);
  const SampleGrid grid(dense.points, std::max(cup.diameter_m / 2, spacing));
  std::vector<std::optional<Grasp>> found(candidates.points.size());
  tbb::parallel_for(size_t(0), candidates.points.size(), [&](size_t i) {
    const Eigen::Vector3d& p = candidates.points[i];
    const Eigen::Vector3d& n = candidates.normals[i];
    const SealCheck seal = CheckSeal(dense, grid, disc, p, n, cup, options.flatness_tolerance_m);
    if (!seal.sealed) return;
    Grasp g;
    g.approach = -n;
    Eigen::Vector3d x, y;
    PerpendicularBasis(g.approach, x, y);
    g.part_from_tool.linear().col(0) = x;
    g.part_from_tool.linear().col(1) = y;
    g.part_from_tool.linear().col(2) = g.approach;
    g.part_from_tool.translation() = p;
    g.quality = seal.quality;
    found[i] = g;
  });
  std::vector<Grasp> out;
  for (auto& g : found)
    if (g) out.push_back(*g);
  return out;
}

}  // namespace vscan::grasping
