#include "physics/mesh_overlap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include <Eigen/Geometry>

#include "physics/mesh_depth.h"

namespace vscan::physics {
namespace {

using Edges = std::vector<std::array<uint32_t, 2>>;

constexpr int kMaxBisections = 40;

// Signed depth is 1-Lipschitz along the segment: no point of it lies deeper than
// (sp + sq + length) / 2. depth() may overstate outside values (a bound), never inside ones.
template <typename Depth>
void Bisect(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double sp, double sq, const Depth& depth,
            double& best, int level) {
  const double length = (q - p).norm();
  if (0.5 * (sp + sq + length) <= best + kMeshOverlapResolution || level >= kMaxBisections) return;
  const Eigen::Vector3d m = 0.5 * (p + q);
  const double sm = depth(m);
  best = std::max(best, sm);
  Bisect(p, m, sp, sm, depth, best, level + 1);
  Bisect(m, q, sm, sq, depth, best, level + 1);
}

// The deepest vertex or edge point (>= 0) of the points joined by edges, by depth(); edges whose
// box misses `target` lie wholly outside it.
template <typename Depth>
double DeepestOf(const std::vector<Eigen::Vector3d>& points, const Edges& edges, const Eigen::AlignedBox3d& target,
                 const Depth& depth) {
  double best = 0.0;
  std::vector<double> value(points.size(), std::numeric_limits<double>::quiet_NaN());
  const auto at = [&](uint32_t i) {
    if (std::isnan(value[i])) value[i] = depth(points[i]);
    return value[i];
  };
  for (const auto& e : edges) {
    Eigen::AlignedBox3d box(points[e[0]]);
    box.extend(points[e[1]]);
    if (!box.intersects(target)) continue;
    const double s0 = at(e[0]), s1 = at(e[1]);
    best = std::max({best, s0, s1});
    Bisect(points[e[0]], points[e[1]], s0, s1, depth, best, 0);
  }
  return best;
}

std::vector<Eigen::Vector3d> Transformed(const std::vector<Eigen::Vector3d>& points, const Pose3& to_from) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back(to_from * p);
  return out;
}

// A solid box of the bin, in the bin frame.
struct Slab {
  Eigen::AlignedBox3d box;
  double Depth(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d centre = box.center(), half = 0.5 * box.sizes();
    const Eigen::Vector3d q = (p - centre).cwiseAbs() - half;
    if ((q.array() <= 0).all()) return -q.maxCoeff();
    return -q.cwiseMax(0.0).norm();
  }
  std::vector<Eigen::Vector3d> Corners() const {
    std::vector<Eigen::Vector3d> out;
    for (int i = 0; i < 8; ++i) out.push_back(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)));
    return out;
  }
};

// Corners differing in one bit (Eigen's corner numbering: bit 0 x, bit 1 y, bit 2 z).
const Edges kBoxEdges = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

// The floor and walls as MakeBinBodies builds them.
std::vector<Slab> BinSlabs(const BinSpec& bin) {
  const double sx = bin.inner_size.x(), sy = bin.inner_size.y(), sz = bin.inner_size.z(), w = bin.wall_thickness;
  const auto slab = [](const Eigen::Vector3d& half, const Eigen::Vector3d& centre) {
    return Slab{Eigen::AlignedBox3d(centre - half, centre + half)};
  };
  return {slab({0.5 * sx + w, 0.5 * sy + w, 0.5 * w}, {0, 0, -0.5 * w}),
          slab({0.5 * w, 0.5 * sy + w, 0.5 * sz}, {0.5 * (sx + w), 0, 0.5 * sz}),
          slab({0.5 * w, 0.5 * sy + w, 0.5 * sz}, {-0.5 * (sx + w), 0, 0.5 * sz}),
          slab({0.5 * sx, 0.5 * w, 0.5 * sz}, {0, 0.5 * (sy + w), 0.5 * sz}),
          slab({0.5 * sx, 0.5 * w, 0.5 * sz}, {0, -0.5 * (sy + w), 0.5 * sz})};
}

struct Placed {
  const MeshDepth* mesh = nullptr;
  Pose3 world_from_part = Pose3::Identity();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // of its bounding box, world
  double radius = 0.0;
};

double PairDepth(const Placed& a, const Placed& b) {
  const Pose3 b_from_a = b.world_from_part.inverse() * a.world_from_part;
  const auto in_b = [&](const Eigen::Vector3d& p) { return b.mesh->SignedDepth(p); };
  const auto in_a = [&](const Eigen::Vector3d& p) { return a.mesh->SignedDepth(p); };
  const double a_in_b = DeepestOf(Transformed(a.mesh->vertices(), b_from_a), a.mesh->edges(), b.mesh->bounds(), in_b);
  const double b_in_a =
      DeepestOf(Transformed(b.mesh->vertices(), b_from_a.inverse()), b.mesh->edges(), a.mesh->bounds(), in_a);
  return std::max(a_in_b, b_in_a);
}

double BoxBinDepth(const Placed& part, const std::vector<Slab>& slabs, const Pose3& bin_from_world) {
  const Pose3 bin_from_part = bin_from_world * part.world_from_part;
  const std::vector<Eigen::Vector3d> points = Transformed(part.mesh->vertices(), bin_from_part);
  const Pose3 part_from_bin = bin_from_part.inverse();
  const auto in_part = [&](const Eigen::Vector3d& p) { return part.mesh->SignedDepth(p); };
  double best = 0.0;
  for (const Slab& slab : slabs) {
    const auto in_slab = [&](const Eigen::Vector3d& p) { return slab.Depth(p); };
    best = std::max(best, DeepestOf(points, part.mesh->edges(), slab.box, in_slab));
    best = std::max(best, DeepestOf(Transformed(slab.Corners(), part_from_bin), kBoxEdges, part.mesh->bounds(), in_part));
  }
  return best;
}

double MeshBinDepth(const Placed& part, const MeshDepth& bin_mesh, const Pose3& bin_from_world) {
  const Pose3 bin_from_part = bin_from_world * part.world_from_part;
  const Eigen::Vector3d centre = bin_from_world * part.centre;
  // Behind the nearest triangle's plane when the point and the part's centre lie on its two sides.
  const auto behind = [&](const Eigen::Vector3d& p) {
    uint32_t triangle = 0;
    const double distance = bin_mesh.Distance(p, &triangle);
    const Eigen::Vector3d n = bin_mesh.Normal(triangle);
    const Eigen::Vector3d& corner = bin_mesh.vertices()[bin_mesh.triangles()[triangle][0]];
    const bool opposite = n.dot(p - corner) * n.dot(centre - corner) < 0;
    return opposite ? distance : -distance;
  };
  const Eigen::AlignedBox3d anywhere(Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity()),
                                     Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()));
  double best = DeepestOf(Transformed(part.mesh->vertices(), bin_from_part), part.mesh->edges(), anywhere, behind);
  const auto in_part = [&](const Eigen::Vector3d& p) { return part.mesh->SignedDepth(p); };
  best = std::max(best, DeepestOf(Transformed(bin_mesh.vertices(), bin_from_part.inverse()), bin_mesh.edges(),
                                  part.mesh->bounds(), in_part));
  return best;
}

}  // namespace

MeshOverlaps MeasureMeshOverlaps(const BinSpec& bin, const std::vector<PartType>& parts,
                                 const std::vector<PlacedPart>& placed) {
  MeshOverlaps out;
  out.resolution_m = kMeshOverlapResolution;
  std::vector<std::unique_ptr<MeshDepth>> meshes(parts.size());
  std::vector<Placed> items;
  items.reserve(placed.size());
  for (const PlacedPart& p : placed) {
    if (!meshes[p.type]) meshes[p.type] = std::make_unique<MeshDepth>(parts[p.type].mesh);
    const Eigen::AlignedBox3d& box = meshes[p.type]->bounds();
    items.push_back({meshes[p.type].get(), p.world_from_part, p.world_from_part * box.center(), 0.5 * box.diagonal().norm()});
  }
  std::vector<double> pair_depths;
  for (size_t i = 0; i < items.size(); ++i) {
    for (size_t j = i + 1; j < items.size(); ++j) {
      const double reach = items[i].radius + items[j].radius;
      if ((items[i].centre - items[j].centre).squaredNorm() > reach * reach) continue;
      const double depth = PairDepth(items[i], items[j]);
      if (depth > 0) pair_depths.push_back(depth);
    }
  }
  const Pose3 bin_from_world = bin.world_from_bin.inverse();
  if (bin.mesh.empty()) {
    const std::vector<Slab> slabs = BinSlabs(bin);
    for (const Placed& part : items) out.max_part_bin_m = std::max(out.max_part_bin_m, BoxBinDepth(part, slabs, bin_from_world));
  } else {
    const MeshDepth bin_mesh(bin.mesh);
    for (const Placed& part : items) {
      out.max_part_bin_m = std::max(out.max_part_bin_m, MeshBinDepth(part, bin_mesh, bin_from_world));
    }
  }
  out.overlapping_pairs = pair_depths.size();
  if (!pair_depths.empty()) {
    std::sort(pair_depths.begin(), pair_depths.end());
    out.max_part_part_m = pair_depths.back();
    const auto rank = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(pair_depths.size())));
    out.p95_part_part_m = pair_depths[std::max<size_t>(rank, 1) - 1];
  }
  return out;
}

}  // namespace vscan::physics
