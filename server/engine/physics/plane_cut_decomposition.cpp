#include "physics/plane_cut_decomposition.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include <Eigen/Geometry>

#include "physics/mesh_depth.h"
#include "physics/part_geometry.h"

namespace vscan::physics {
namespace {

using Polygon = std::vector<Eigen::Vector3d>;

// Below a plane: normal . x <= offset.
struct Plane {
  Eigen::Vector3d normal;
  double offset;
};

// Samples on one hull are at most about this many (fewer while cuts are compared): the step grows
// on large hulls.
constexpr double kMaxSamplesPerHull = 600;
constexpr double kMaxSamplesPerTrial = 300;

// The mesh's solid, queried in coordinates relative to the centre.
class Solid {
 public:
  Solid(const TriangleMesh& mesh, const Eigen::Vector3d& centre) : depth_(mesh), centre_(centre) {}

  // Distance from p to the solid, 0 inside. Points nearer the surface than `near` skip the inside
  // test and report their distance to it: they cannot decide a reach larger than `near`.
  double Outside(const Eigen::Vector3d& p, double near) const {
    const Eigen::Vector3d q = p + centre_;
    const double d = depth_.Distance(q);
    if (d <= near) return d;
    return depth_.Inside(q) ? 0.0 : d;
  }

 private:
  MeshDepth depth_;
  Eigen::Vector3d centre_;
};

// Points of triangle (a, b, c) about `step` apart, its corners included: a grid along the two
// edges at the corner opposite the longest, so that a sliver gets a row, not a square.
void TriangleSamples(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, double step,
                     std::vector<Eigen::Vector3d>& out) {
  const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
  Eigen::Vector3d o = c, u = a - c, v = b - c;
  if (ca >= ab && ca >= bc) o = b, u = a - b, v = c - b;
  if (bc >= ab && bc >= ca) o = a, u = b - a, v = c - a;
  const int nu = std::max(1, static_cast<int>(std::ceil(u.norm() / step)));
  const int nv = std::max(1, static_cast<int>(std::ceil(v.norm() / step)));
  for (int i = 0; i <= nu; ++i) {
    for (int j = 0; j <= nv; ++j) {
      const double s = static_cast<double>(i) / nu, t = static_cast<double>(j) / nv;
      if (s + t <= 1.0 + 1e-9) out.push_back(o + s * u + t * v);
    }
  }
}

double FaceArea(const HullFace& face) {
  Eigen::Vector3d twice = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < face.corners.size(); ++i) twice += face.corners[i].cross(face.corners[(i + 1) % face.corners.size()]);
  return 0.5 * twice.norm();
}

// The farthest of a hull's surface samples from the solid: its distance and the sample.
struct Farthest {
  double distance = 0.0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

Farthest Reach(const std::vector<HullFace>& faces, const Solid& solid, double step, double near, double max_samples) {
  double area = 0.0;
  for (const HullFace& face : faces) area += FaceArea(face);
  step = std::max(step, std::sqrt(area / max_samples));
  std::vector<Eigen::Vector3d> samples;
  for (const HullFace& face : faces) {
    for (size_t i = 1; i + 1 < face.corners.size(); ++i) {
      TriangleSamples(face.corners[0], face.corners[i], face.corners[i + 1], step, samples);
    }
  }
  Farthest farthest;
  for (const Eigen::Vector3d& p : samples) {
    const double d = solid.Outside(p, near);
    if (d > farthest.distance) farthest = {d, p};
  }
  return farthest;
}

// A piece of the solid: the mesh's surface within its cell, and its hull.
struct Cell {
  std::vector<Polygon> surface;
  std::vector<HullFace> faces;
  double volume = 0.0;
  double reach = 0.0;    // HullReach of its hull
  Eigen::Vector3d farthest = Eigen::Vector3d::Zero();  // where its hull reaches that far
  bool settled = false;  // no cut brings it nearer the bound
};

struct Context {
  const Solid& solid;
  double bound;
  double step;
  double near;
  double least_volume_gain;  // a cut that leaves the worst reach must take this much hull volume
};

// The cell's reach and where it is, from up to max_samples samples of its hull.
void Measure(Cell& cell, const Context& context, double max_samples) {
  const Farthest farthest = Reach(cell.faces, context.solid, context.step, context.near, max_samples);
  cell.reach = farthest.distance;
  cell.farthest = farthest.point;
}

Cell MakeCell(std::vector<Polygon> surface, const Context& context, double max_samples = kMaxSamplesPerHull) {
  Cell cell;
  cell.surface = std::move(surface);
  std::vector<Eigen::Vector3d> corners;
  for (const Polygon& polygon : cell.surface) corners.insert(corners.end(), polygon.begin(), polygon.end());
  if (corners.size() >= 4) cell.faces = HullFaces(corners);
  if (cell.faces.size() < 4) {  // flat: nothing to cut and no volume
    cell.faces.clear();
    return cell;
  }
  for (const HullFace& face : cell.faces) cell.volume += face.offset * FaceArea(face) / 3.0;
  Measure(cell, context, max_samples);
  return cell;
}

// Sutherland-Hodgman against both sides at once; a polygon on the plane goes below.
void Split(const std::vector<Polygon>& in, const Plane& plane, std::vector<Polygon>& below,
           std::vector<Polygon>& above) {
  for (const Polygon& polygon : in) {
    std::vector<double> d(polygon.size());
    bool any_below = false, any_above = false;
    for (size_t i = 0; i < polygon.size(); ++i) {
      d[i] = plane.normal.dot(polygon[i]) - plane.offset;
      any_below |= d[i] < 0, any_above |= d[i] > 0;
    }
    if (!any_above) {
      below.push_back(polygon);
      continue;
    }
    if (!any_below) {
      above.push_back(polygon);
      continue;
    }
    Polygon low, high;
    for (size_t i = 0; i < polygon.size(); ++i) {
      const size_t j = (i + 1) % polygon.size();
      if (d[i] <= 0) low.push_back(polygon[i]);
      if (d[i] >= 0) high.push_back(polygon[i]);
      if ((d[i] < 0 && d[j] > 0) || (d[i] > 0 && d[j] < 0)) {
        const Eigen::Vector3d p = polygon[i] + (d[i] / (d[i] - d[j])) * (polygon[j] - polygon[i]);
        low.push_back(p);
        high.push_back(p);
      }
    }
    if (low.size() >= 3) below.push_back(std::move(low));
    if (high.size() >= 3) above.push_back(std::move(high));
  }
}

// The cells a cut (one plane or two) leaves, with their worst reach and total volume.
struct Trial {
  std::vector<Cell> cells;
  double reach = 0.0;
  double volume = 0.0;
};

Trial Cut(const std::vector<Polygon>& surface, const std::vector<Plane>& planes, const Context& context,
          double max_samples) {
  std::vector<std::vector<Polygon>> parts = {surface};
  for (const Plane& plane : planes) {
    std::vector<std::vector<Polygon>> next;
    for (const auto& part : parts) {
      std::vector<Polygon> below, above;
      Split(part, plane, below, above);
      if (!below.empty()) next.push_back(std::move(below));
      if (!above.empty()) next.push_back(std::move(above));
    }
    parts = std::move(next);
  }
  Trial trial;
  for (auto& part : parts) {
    trial.cells.push_back(MakeCell(std::move(part), context, max_samples));
    trial.reach = std::max(trial.reach, trial.cells.back().reach);
    trial.volume += trial.cells.back().volume;
  }
  return trial;
}

// Reach first, in steps of an eighth of the bound, then volume.
bool Better(const Trial& a, const Trial& b, double bound) {
  const double bucket = bound / 8;
  const double ka = std::floor(a.reach / bucket), kb = std::floor(b.reach / bucket);
  if (ka != kb) return ka < kb;
  return a.volume < b.volume;
}

const Eigen::Vector3d kAxes[] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};

// Planes of the surface where it lies deepest under the cell's hull (a notch's own faces, at any
// angle), and across each axis through those points and at a grid of sixths of the cell's extent.
struct Candidates {
  std::vector<Plane> planes;
  std::vector<Eigen::Vector3d> deep_normals;  // of the surface deepest under the hull, one a direction
};

Candidates CandidatePlanes(const Cell& cell, double bound) {
  struct Deep {
    double depth;
    Eigen::Vector3d point, normal;
  };
  std::vector<Deep> deep;
  for (const Polygon& polygon : cell.surface) {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < polygon.size(); ++i) normal += polygon[i].cross(polygon[(i + 1) % polygon.size()]);
    for (const Eigen::Vector3d& p : polygon) {
      double depth = INFINITY;
      for (const HullFace& face : cell.faces) depth = std::min(depth, face.offset - face.normal.dot(p));
      if (depth > bound && normal.norm() > 0) deep.push_back({depth, p, normal.normalized()});
    }
  }
  std::sort(deep.begin(), deep.end(), [](const Deep& a, const Deep& b) { return a.depth > b.depth; });
  Candidates out;
  std::vector<Plane>& planes = out.planes;
  std::vector<Eigen::Vector3d>& normals = out.deep_normals;
  for (const Deep& d : deep) {
    if (normals.size() == 6) break;
    // One plane per direction: a notch's face is many triangles.
    const bool seen = std::any_of(normals.begin(), normals.end(), [&](const Eigen::Vector3d& n) {
      return std::abs(n.dot(d.normal)) > 0.999;
    });
    if (seen) continue;
    normals.push_back(d.normal);
    planes.push_back({d.normal, d.normal.dot(d.point)});
  }
  for (const Eigen::Vector3d& axis : kAxes) {
    double lo = INFINITY, hi = -INFINITY;
    for (const HullFace& face : cell.faces) {
      for (const Eigen::Vector3d& p : face.corners) lo = std::min(lo, axis.dot(p)), hi = std::max(hi, axis.dot(p));
    }
    if (!(hi - lo > bound)) continue;
    std::vector<double> offsets;
    for (size_t i = 0; i < deep.size() && i < 8; ++i) offsets.push_back(axis.dot(deep[i].point));
    for (int k = 1; k < 6; ++k) offsets.push_back(lo + (hi - lo) * k / 6.0);
    std::sort(offsets.begin(), offsets.end());
    const double apart = 1e-6 * (hi - lo);
    double last = -INFINITY;
    for (double offset : offsets) {
      if (offset - lo <= apart || hi - offset <= apart || offset - last <= apart) continue;
      planes.push_back({axis, offset});
      last = offset;
    }
  }
  return out;
}

// The chosen cut's cells at the full sampling.
Trial Remeasured(Trial trial, const Context& context) {
  for (Cell& cell : trial.cells) Measure(cell, context, kMaxSamplesPerHull);
  return trial;
}

// The best single cut, or quarters about the hull's middle or its farthest point, if it brings the cell
// nearer.
std::optional<Trial> BestCut(const Cell& cell, const Context& context, size_t room) {
  const double bucket = context.bound / 8;
  std::optional<Trial> best;
  const Candidates candidates = CandidatePlanes(cell, context.bound);
  for (const Plane& plane : candidates.planes) {
    Trial trial = Cut(cell.surface, {plane}, context, kMaxSamplesPerTrial);
    if (trial.cells.size() != 2) continue;
    if (!best || Better(trial, *best, context.bound)) best = std::move(trial);
  }
  // First what brings the worst reach down most: one plane, or quarters (a bore or a ring, which no
  // single plane opens) about the hull's middle or about where it reaches farthest (a hole's axis).
  std::optional<Trial> quarters;
  if (room >= 4) {
    Eigen::AlignedBox3d box;
    for (const HullFace& face : cell.faces) {
      for (const Eigen::Vector3d& p : face.corners) box.extend(p);
    }
    // Pairs of the part's axes, and of the deep surface's normals: planes along a tilted bore.
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs = {
        {kAxes[0], kAxes[1]}, {kAxes[1], kAxes[2]}, {kAxes[2], kAxes[0]}};
    // Two normals of a bore's wall span the plane across it; their cross product is its axis.
    const auto& deep = candidates.deep_normals;
    for (size_t i = 0; i < deep.size() && i < 4; ++i) {
      for (size_t j = i + 1; j < deep.size() && j < 4; ++j) {
        const Eigen::Vector3d axis = deep[i].cross(deep[j]);
        if (axis.norm() > 0.1) pairs.emplace_back(deep[i], axis.normalized().cross(deep[i]));
      }
    }
    for (const Eigen::Vector3d& middle : {Eigen::Vector3d(box.center()), cell.farthest}) {
      for (const auto& [a, b] : pairs) {
        Trial trial = Cut(cell.surface, {{a, a.dot(middle)}, {b, b.dot(middle)}}, context, kMaxSamplesPerTrial);
        if (trial.cells.size() < 3) continue;
        if (!quarters || Better(trial, *quarters, context.bound)) quarters = std::move(trial);
      }
    }
  }
  // Quarters must do better than the best plane by more than their extra pieces' worth.
  const bool planes_first = best && (!quarters || best->reach <= quarters->reach + 2 * bucket);
  if (planes_first && best->reach < cell.reach - bucket) return Remeasured(std::move(*best), context);
  if (quarters && quarters->reach < cell.reach - bucket) return Remeasured(std::move(*quarters), context);
  // Then a plane that keeps the worst reach but takes hull volume (one of two equal notches).
  if (best && best->reach <= cell.reach + bucket && cell.volume - best->volume > context.least_volume_gain) {
    return Remeasured(std::move(*best), context);
  }
  return std::nullopt;
}

}  // namespace

double HullReach(const TriangleMesh& mesh, const Eigen::Vector3d& centre, const std::vector<Eigen::Vector3d>& points,
                 double step) {
  const Solid solid(mesh, centre);
  const std::vector<HullFace> faces = HullFaces(points);
  return faces.size() < 4 ? 0.0 : Reach(faces, solid, step, 0.0, INFINITY).distance;
}

std::vector<std::vector<Eigen::Vector3d>> PlaneCutPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                         const PlaneCutOptions& options) {
  const Solid solid(mesh, centre);
  const double bound = options.concavity_m;
  // A cut that leaves the worst reach must take 2% of the whole hull's volume.
  const double least_volume_gain = 0.02 * HullVolume(ExactHull(mesh, centre));
  const Context context{solid, bound, 0.5 * bound, bound / 8, least_volume_gain};
  std::vector<Polygon> surface;
  surface.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    Polygon triangle;
    for (int k = 0; k < 3; ++k) triangle.push_back(mesh.vertices[t[k]].cast<double>() - centre);
    surface.push_back(std::move(triangle));
  }
  std::vector<Cell> cells;
  cells.push_back(MakeCell(std::move(surface), context));
  while (cells.size() < options.max_pieces) {
    size_t worst = cells.size();
    for (size_t i = 0; i < cells.size(); ++i) {
      if (!cells[i].settled && cells[i].reach > bound && (worst == cells.size() || cells[i].reach > cells[worst].reach)) {
        worst = i;
      }
    }
    if (worst == cells.size()) break;
    std::optional<Trial> cut = BestCut(cells[worst], context, options.max_pieces - cells.size() + 1);
    if (!cut) {
      cells[worst].settled = true;
      continue;
    }
    cells[worst] = std::move(cut->cells[0]);
    for (size_t i = 1; i < cut->cells.size(); ++i) cells.push_back(std::move(cut->cells[i]));
  }
  std::vector<std::vector<Eigen::Vector3d>> pieces;
  for (const Cell& cell : cells) {
    if (cell.faces.empty()) continue;
    std::vector<Eigen::Vector3d> corners;
    for (const Polygon& polygon : cell.surface) corners.insert(corners.end(), polygon.begin(), polygon.end());
    pieces.push_back(HullVertices(corners));
  }
  return pieces;
}

}  // namespace vscan::physics
