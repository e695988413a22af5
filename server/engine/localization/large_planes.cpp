#include "localization/large_planes.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <Eigen/Geometry>

#include "localization/support_plane.h"

namespace vscan::localization {
namespace {

// Union-find over cell indices.
size_t Root(std::vector<size_t>& parent, size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

uint64_t CellKey(const Eigen::Vector3f& p, double inverse_link) {
  const auto field = [&](float v) {
    return static_cast<uint64_t>(std::clamp<int64_t>(static_cast<int64_t>(std::floor(v * inverse_link)) + (1 << 20), 0,
                                                     (1 << 21) - 1));
  };
  return (field(p.x()) << 42) | (field(p.y()) << 21) | field(p.z());
}

// Marks the pieces of `members` (indices into cloud, on the plane with that normal) that are wide
// structures.
void MarkWidePieces(const OrientedPoints& cloud, const std::vector<uint32_t>& members, const Eigen::Vector3d& normal,
                      const LargePlaneSettings& settings, std::vector<bool>& marked) {
  const double inverse_link = 1.0 / settings.link;
  std::unordered_map<uint64_t, size_t> cells;
  std::vector<size_t> cell_of(members.size());
  for (size_t k = 0; k < members.size(); ++k) {
    cell_of[k] = cells.emplace(CellKey(cloud.points[members[k]], inverse_link), cells.size()).first->second;
  }
  std::vector<size_t> parent(cells.size());
  std::iota(parent.begin(), parent.end(), 0);
  constexpr uint64_t kField = (uint64_t{1} << 21) - 1;
  for (const auto& [key, index] : cells) {
    const auto x = static_cast<int64_t>(key >> 42), y = static_cast<int64_t>((key >> 21) & kField),
               z = static_cast<int64_t>(key & kField);
    for (int64_t dx = -1; dx <= 1; ++dx) {
      for (int64_t dy = -1; dy <= 1; ++dy) {
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const uint64_t other = (static_cast<uint64_t>(x + dx) << 42) | (static_cast<uint64_t>(y + dy) << 21) |
                                 static_cast<uint64_t>(z + dz);
          const auto found = cells.find(other);
          if (found != cells.end()) parent[Root(parent, index)] = Root(parent, found->second);
        }
      }
    }
  }
  // Per piece: its extent, and in the plane's own axes its rectangle and the cells it occupies.
  const Eigen::Vector3f u = normal.cast<float>().unitOrthogonal(), v = normal.cast<float>().cross(u);
  struct Piece {
    Eigen::AlignedBox3f box;
    Eigen::AlignedBox2f rectangle;
    size_t cells = 0;
  };
  std::unordered_map<size_t, Piece> pieces;
  for (size_t k = 0; k < members.size(); ++k) {
    Piece& piece = pieces[Root(parent, cell_of[k])];
    const Eigen::Vector3f& p = cloud.points[members[k]];
    piece.box.extend(p);
    piece.rectangle.extend(Eigen::Vector2f(p.dot(u), p.dot(v)));
  }
  for (size_t c = 0; c < parent.size(); ++c) ++pieces[Root(parent, c)].cells;
  const bool parallel = settings.support_normal && std::abs(settings.support_normal->dot(normal)) >= 0.866;
  const auto structure = [&](const Piece& piece) {
    if (piece.box.diagonal().norm() <= settings.min_extent) return false;
    if (!parallel) return true;
    const Eigen::Vector2f sides = piece.rectangle.sizes() * static_cast<float>(inverse_link) + Eigen::Vector2f::Ones();
    return static_cast<double>(piece.cells) < settings.max_parallel_fill * static_cast<double>(sides.x() * sides.y());
  };
  for (size_t k = 0; k < members.size(); ++k) {
    if (structure(pieces[Root(parent, cell_of[k])])) marked[members[k]] = true;
  }
}

}  // namespace

std::vector<bool> MarkLargePlanes(const OrientedPoints& cloud, const LargePlaneSettings& settings) {
  std::vector<bool> marked(cloud.points.size(), false);
  std::vector<uint32_t> remaining(cloud.points.size());
  std::iota(remaining.begin(), remaining.end(), 0u);
  constexpr double kMinNormalCos = 0.866;  // 30 degrees
  for (size_t k = 0; k < settings.max_planes && remaining.size() >= settings.min_points; ++k) {
    std::vector<Eigen::Vector3f> points(remaining.size());
    for (size_t i = 0; i < remaining.size(); ++i) points[i] = cloud.points[remaining[i]];
    const double min_share = static_cast<double>(settings.min_points) / static_cast<double>(points.size());
    const auto plane = FindDominantPlane(points, settings.distance, min_share, settings.seed + k);
    if (!plane) break;
    std::vector<uint32_t> members, rest;
    for (const uint32_t i : remaining) {
      const bool on = plane->Distance(cloud.points[i]) <= settings.distance &&
                      std::abs(plane->normal.cast<float>().dot(cloud.normals[i])) >= kMinNormalCos;
      (on ? members : rest).push_back(i);
    }
    if (members.size() < settings.min_points) break;
    MarkWidePieces(cloud, members, plane->normal, settings, marked);
    // The plane's small pieces (parts' faces) stay in the scan but leave the next plane's search.
    remaining = std::move(rest);
  }
  return marked;
}

}  // namespace vscan::localization
