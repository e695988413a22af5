#include "physics/mesh_overlap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include <Eigen/Geometry>

#include "physics/mesh_depth.h"

namespace vscan::physics {
namespace {

using Edges = std::vector<std::array<uint32_t, 2>>;

constexpr int kMaxBisections = 40;

// The deepest point found (in the frame of the mesh it lies in) and its depth.
struct Deepest {
  double depth = 0.0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  void Take(double d, const Eigen::Vector3d& p) {
    if (d > depth) depth = d, point = p;
  }
};

// Signed depth is 1-Lipschitz along the segment: no point of it lies deeper than
// (sp + sq + length) / 2. depth() may overstate outside values (a bound), never inside ones.
template <typename Depth>
void Bisect(const Eigen::Vector3d& p, const Eigen::Vector3d& q, double sp, double sq, const Depth& depth,
            Deepest& best, int level) {
  const double length = (q - p).norm();
  if (0.5 * (sp + sq + length) <= best.depth + kMeshOverlapResolution || level >= kMaxBisections) return;
  const Eigen::Vector3d m = 0.5 * (p + q);
  const double sm = depth(m);
  best.Take(sm, m);
  Bisect(p, m, sp, sm, depth, best, level + 1);
  Bisect(m, q, sm, sq, depth, best, level + 1);
}

// The deepest vertex or edge point (>= 0) of the points joined by edges, by depth(); edges whose
// box misses `target` lie wholly outside it.
template <typename Depth>
Deepest DeepestOf(const std::vector<Eigen::Vector3d>& points, const Edges& edges, const Eigen::AlignedBox3d& target,
                  const Depth& depth) {
  Deepest best;
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
    best.Take(s0, points[e[0]]);
    best.Take(s1, points[e[1]]);
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

// A part's overlap with another part or the bin: its depth, and the world translation of the
// part that would end it (the other part, if any, would move the opposite way).
struct Overlap {
  double depth = 0.0;
  Eigen::Vector3d push = Eigen::Vector3d::Zero();
};

// From a point inside a mesh to its nearest surface point: how the mesh must move (the opposite
// way) to leave the point outside it; in the mesh's frame.
Eigen::Vector3d OutOf(const MeshDepth& mesh, const Eigen::Vector3d& inside) {
  uint32_t triangle = 0;
  mesh.Distance(inside, &triangle);
  const auto& t = mesh.triangles()[triangle];
  const Eigen::Vector3d q =
      ClosestPointOnTriangle(inside, mesh.vertices()[t[0]], mesh.vertices()[t[1]], mesh.vertices()[t[2]]);
  return q - inside;
}

// push moves part a (b moves by -push).
Overlap PairOverlap(const Placed& a, const Placed& b) {
  const Pose3 b_from_a = b.world_from_part.inverse() * a.world_from_part;
  const auto in_b = [&](const Eigen::Vector3d& p) { return b.mesh->SignedDepth(p); };
  const auto in_a = [&](const Eigen::Vector3d& p) { return a.mesh->SignedDepth(p); };
  const Deepest a_in_b = DeepestOf(Transformed(a.mesh->vertices(), b_from_a), a.mesh->edges(), b.mesh->bounds(), in_b);
  const Deepest b_in_a =
      DeepestOf(Transformed(b.mesh->vertices(), b_from_a.inverse()), b.mesh->edges(), a.mesh->bounds(), in_a);
  Overlap out;
  if (a_in_b.depth >= b_in_a.depth && a_in_b.depth > 0) {
    out.depth = a_in_b.depth;
    out.push = b.world_from_part.linear() * OutOf(*b.mesh, a_in_b.point);  // a's point to b's surface
  } else if (b_in_a.depth > 0) {
    out.depth = b_in_a.depth;
    out.push = -(a.world_from_part.linear() * OutOf(*a.mesh, b_in_a.point));
  }
  return out;
}

Overlap BoxBinOverlap(const Placed& part, const std::vector<Slab>& slabs, const Pose3& bin_from_world) {
  const Pose3 bin_from_part = bin_from_world * part.world_from_part;
  const std::vector<Eigen::Vector3d> points = Transformed(part.mesh->vertices(), bin_from_part);
  const Pose3 part_from_bin = bin_from_part.inverse();
  const auto in_part = [&](const Eigen::Vector3d& p) { return part.mesh->SignedDepth(p); };
  Overlap out;
  for (const Slab& slab : slabs) {
    const auto in_slab = [&](const Eigen::Vector3d& p) { return slab.Depth(p); };
    const Deepest part_in_slab = DeepestOf(points, part.mesh->edges(), slab.box, in_slab);
    if (part_in_slab.depth > out.depth) {
      // Out through the slab's nearest face.
      const Eigen::Vector3d offset = part_in_slab.point - slab.box.center();
      const Eigen::Vector3d q = offset.cwiseAbs() - 0.5 * slab.box.sizes();
      int axis = 0;
      q.maxCoeff(&axis);
      Eigen::Vector3d push = Eigen::Vector3d::Zero();
      push[axis] = (offset[axis] >= 0 ? 1.0 : -1.0) * part_in_slab.depth;
      out = {part_in_slab.depth, bin_from_world.linear().transpose() * push};
    }
    const Deepest slab_in_part =
        DeepestOf(Transformed(slab.Corners(), part_from_bin), kBoxEdges, part.mesh->bounds(), in_part);
    if (slab_in_part.depth > out.depth) {
      out = {slab_in_part.depth, -(part.world_from_part.linear() * OutOf(*part.mesh, slab_in_part.point))};
    }
  }
  return out;
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
  const auto in_part = [&](const Eigen::Vector3d& p) { return part.mesh->SignedDepth(p); };
  return std::max(
      DeepestOf(Transformed(part.mesh->vertices(), bin_from_part), part.mesh->edges(), anywhere, behind).depth,
      DeepestOf(Transformed(bin_mesh.vertices(), bin_from_part.inverse()), bin_mesh.edges(), part.mesh->bounds(),
                in_part)
          .depth);
}

// Overlaps found so far: a pair or a part's bin overlap is measured again only when one of its
// parts moved since.
struct OverlapCache {
  std::map<std::pair<size_t, size_t>, Overlap> pairs;
  std::vector<Overlap> bin;
  std::vector<double> mesh_bin;
};

void Refresh(const BinSpec& bin, const std::vector<Placed>& items, const MeshDepth* bin_mesh,
             const std::vector<bool>& dirty, OverlapCache& cache) {
  for (size_t i = 0; i < items.size(); ++i) {
    for (size_t j = i + 1; j < items.size(); ++j) {
      if (!dirty[i] && !dirty[j]) continue;
      const double reach = items[i].radius + items[j].radius;
      const bool near = (items[i].centre - items[j].centre).squaredNorm() <= reach * reach;
      const Overlap o = near ? PairOverlap(items[i], items[j]) : Overlap{};
      if (o.depth > 0) {
        cache.pairs[{i, j}] = o;
      } else {
        cache.pairs.erase({i, j});
      }
    }
  }
  const Pose3 bin_from_world = bin.world_from_bin.inverse();
  if (bin_mesh == nullptr) {
    const std::vector<Slab> slabs = BinSlabs(bin);
    cache.bin.resize(items.size());
    for (size_t i = 0; i < items.size(); ++i) {
      if (dirty[i]) cache.bin[i] = BoxBinOverlap(items[i], slabs, bin_from_world);
    }
  } else {
    cache.mesh_bin.resize(items.size());
    for (size_t i = 0; i < items.size(); ++i) {
      if (dirty[i]) cache.mesh_bin[i] = MeshBinDepth(items[i], *bin_mesh, bin_from_world);
    }
  }
}

MeshOverlaps Summarize(const OverlapCache& cache) {
  MeshOverlaps out;
  out.resolution_m = kMeshOverlapResolution;
  std::vector<double> pair_depths;
  for (const auto& [key, o] : cache.pairs) pair_depths.push_back(o.depth);
  for (const Overlap& o : cache.bin) out.max_part_bin_m = std::max(out.max_part_bin_m, o.depth);
  for (double d : cache.mesh_bin) out.max_part_bin_m = std::max(out.max_part_bin_m, d);
  out.overlapping_pairs = pair_depths.size();
  if (!pair_depths.empty()) {
    std::sort(pair_depths.begin(), pair_depths.end());
    out.max_part_part_m = pair_depths.back();
    const auto rank = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(pair_depths.size())));
    out.p95_part_part_m = pair_depths[std::max<size_t>(rank, 1) - 1];
  }
  return out;
}

struct Prepared {
  std::vector<std::unique_ptr<MeshDepth>> meshes;
  std::vector<Placed> items;
  std::unique_ptr<MeshDepth> bin_mesh;
};

Prepared Prepare(const BinSpec& bin, const std::vector<PartType>& parts, const std::vector<PlacedPart>& placed) {
  Prepared out;
  out.meshes.resize(parts.size());
  out.items.reserve(placed.size());
  for (const PlacedPart& p : placed) {
    if (!out.meshes[p.type]) out.meshes[p.type] = std::make_unique<MeshDepth>(parts[p.type].mesh);
    const Eigen::AlignedBox3d& box = out.meshes[p.type]->bounds();
    out.items.push_back(
        {out.meshes[p.type].get(), p.world_from_part, p.world_from_part * box.center(), 0.5 * box.diagonal().norm()});
  }
  if (!bin.mesh.empty()) out.bin_mesh = std::make_unique<MeshDepth>(bin.mesh);
  return out;
}

}  // namespace

MeshOverlaps MeasureMeshOverlaps(const BinSpec& bin, const std::vector<PartType>& parts,
                                 const std::vector<PlacedPart>& placed) {
  const Prepared prepared = Prepare(bin, parts, placed);
  OverlapCache cache;
  Refresh(bin, prepared.items, prepared.bin_mesh.get(), std::vector<bool>(placed.size(), true), cache);
  return Summarize(cache);
}

MeshOverlaps SeparateMeshOverlaps(const BinSpec& bin, const std::vector<PartType>& parts,
                                  std::vector<PlacedPart>& placed, double bound, int rounds) {
  Prepared prepared = Prepare(bin, parts, placed);
  const size_t n = placed.size();
  std::vector<Eigen::Vector3d> moved(n, Eigen::Vector3d::Zero());
  const Pose3 bin_from_world = bin.world_from_bin.inverse();
  const bool box_bin = prepared.bin_mesh == nullptr;
  // Each part's vertices' bounding box in the bin frame: a box bin's floor and walls are planes
  // of that frame, so a move that keeps the box inside the interior pushes no vertex into them.
  std::vector<Eigen::AlignedBox3d> extent(n);
  for (size_t i = 0; i < n; ++i) {
    for (const auto& v : prepared.items[i].mesh->vertices()) extent[i].extend(bin_from_world * (placed[i].world_from_part * v));
  }
  const BinInterior interior = InteriorOf(bin);
  // The share of a world move part i can make without entering the floor or a wall further
  // (the open top does not limit it).
  const auto clipped = [&](size_t i, const Eigen::Vector3d& move) -> Eigen::Vector3d {
    if (!box_bin) return move;
    Eigen::Vector3d m = bin_from_world.linear() * move;
    for (int k = 0; k < 3; ++k) {
      m[k] = std::max(m[k], std::min(0.0, interior.lo[k] - extent[i].min()[k]));
      if (k < 2) m[k] = std::min(m[k], std::max(0.0, interior.hi[k] - extent[i].max()[k]));
    }
    return bin.world_from_bin.linear() * m;
  };
  const auto apply = [&](size_t i, const Eigen::Vector3d& m) {
    placed[i].world_from_part.pretranslate(m);
    prepared.items[i].world_from_part = placed[i].world_from_part;
    prepared.items[i].centre += m;
    extent[i].translate(bin_from_world.linear() * m);
    moved[i] += m;
  };
  // A pushed pair is left this far apart past contact, so that its deepest point leaves the other
  // mesh even where the surface curves.
  const double slack = 0.25 * bound;
  std::vector<bool> dirty(n, true);
  OverlapCache cache;
  for (int round = 0;; ++round) {
    Refresh(bin, prepared.items, prepared.bin_mesh.get(), dirty, cache);
    MeshOverlaps summary = Summarize(cache);
    const bool within = summary.max_part_part_m <= bound && (!box_bin || summary.max_part_bin_m <= bound);
    if (within || round == rounds) {
      for (const Eigen::Vector3d& m : moved) {
        summary.max_move_m = std::max(summary.max_move_m, m.norm());
        if (m.squaredNorm() > 0) ++summary.moved_parts;
      }
      summary.rounds = round;
      return summary;
    }
    // The overlaps past the bound, deepest first (a part's bin overlap as the pair (i, n)), each
    // pushed apart in turn and its parts' overlaps measured again at once, before the next one
    // (Gauss-Seidel): summed pushes made parts wedged between others swing from side to side.
    std::vector<std::pair<double, std::pair<size_t, size_t>>> over;
    for (const auto& [key, o] : cache.pairs) {
      if (o.depth > bound) over.push_back({o.depth, key});
    }
    for (size_t i = 0; i < cache.bin.size(); ++i) {
      if (cache.bin[i].depth > bound) over.push_back({cache.bin[i].depth, {i, n}});
    }
    std::sort(over.begin(), over.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& entry : over) {
      const auto [i, j] = entry.second;
      Overlap o;
      if (j == n) {
        o = cache.bin[i];
      } else if (const auto it = cache.pairs.find(entry.second); it != cache.pairs.end()) {
        o = it->second;
      }
      const double length = o.push.norm();
      if (o.depth <= bound || !(length > 0)) continue;  // an earlier push in this round undid it
      const Eigen::Vector3d push = (o.depth + slack) / length * o.push;
      std::fill(dirty.begin(), dirty.end(), false);
      dirty[i] = true;
      if (j == n) {  // the bin does not move
        apply(i, push);
      } else {
        // Half each; what the floor or a wall stops of one part's half, the other part takes.
        Eigen::Vector3d a = clipped(i, 0.5 * push);
        const Eigen::Vector3d b = clipped(j, -push + a);
        a = clipped(i, push + b);
        apply(i, a);
        apply(j, b);
        dirty[j] = true;
      }
      Refresh(bin, prepared.items, prepared.bin_mesh.get(), dirty, cache);
    }
    std::fill(dirty.begin(), dirty.end(), false);
  }
}

}  // namespace vscan::physics
