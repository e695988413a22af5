#include "service/model/model_crop.h"

#include <algorithm>
#include <limits>

namespace vscan::service {
namespace {

// n . x <= d
struct HalfSpace {
  Eigen::Vector3d n;
  double d;
};

std::vector<HalfSpace> Planes(const ModelCrop& crop) {
  switch (crop.kind) {
    case ModelCrop::Kind::kNone: return {};
    case ModelCrop::Kind::kBounds: {
      std::vector<HalfSpace> planes;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
        planes.push_back({e, crop.box.max[k]});
        planes.push_back({-e, -crop.box.min[k]});
      }
      return planes;
    }
    case ModelCrop::Kind::kCylinder:
      return {{-crop.axis, -crop.axis.dot(crop.base)}, {crop.axis, crop.axis.dot(crop.base) + crop.height}};
  }
  return {};
}

using Polygon = std::vector<Eigen::Vector3d>;

// Sutherland-Hodgman against one half-space.
Polygon Clip(const Polygon& polygon, const HalfSpace& h) {
  Polygon out;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector3d& a = polygon[i];
    const Eigen::Vector3d& b = polygon[(i + 1) % polygon.size()];
    const double da = h.n.dot(a) - h.d;
    const double db = h.n.dot(b) - h.d;
    if (da <= 0) out.push_back(a);
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

bool RadiallyInside(const ModelCrop& crop, const Eigen::Vector3d& p) {
  const Eigen::Vector3d r = p - crop.base;
  return (r - crop.axis * crop.axis.dot(r)).norm() <= crop.radius;
}

}  // namespace

bool ModelCrop::Contains(const Eigen::Vector3f& p) const {
  const Eigen::Vector3d q = p.cast<double>();
  switch (kind) {
    case Kind::kNone: return true;
    case Kind::kBounds: return (q.array() >= box.min.array()).all() && (q.array() <= box.max.array()).all();
    case Kind::kCylinder: {
      const double h = axis.dot(q - base);
      return h >= 0 && h <= height && RadiallyInside(*this, q);
    }
  }
  return true;
}

ModelCrop BoxCrop(const ModelBox& box) {
  ModelCrop crop;
  crop.kind = ModelCrop::Kind::kBounds;
  crop.box = box;
  return crop;
}

ModelCrop CylinderAround(const TriangleMesh& truth, const Eigen::Vector3d& axis_point, const Eigen::Vector3d& axis) {
  ModelCrop crop;
  if (truth.vertices.empty()) return crop;
  const Eigen::Vector3d u = axis.normalized();
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  double radius = 0;
  Eigen::Vector3f min, max;
  truth.Bounds(min, max);
  const double size = (max - min).cast<double>().norm();
  for (const Eigen::Vector3f& v : truth.vertices) {
    const Eigen::Vector3d r = v.cast<double>() - axis_point;
    const double h = u.dot(r);
    low = std::min(low, h);
    high = std::max(high, h);
    radius = std::max(radius, (r - u * h).norm());
  }
  crop.kind = ModelCrop::Kind::kCylinder;
  crop.axis = u;
  crop.base = axis_point + u * (low + kCropLift);
  crop.radius = radius + kCropGrowth * size;
  crop.height = std::max(0.0, high + kCropGrowth * size - (low + kCropLift));
  return crop;
}

std::vector<Eigen::Vector3f> CropPoints(std::span<const Eigen::Vector3f> points, const ModelCrop& crop) {
  std::vector<Eigen::Vector3f> kept;
  kept.reserve(points.size());
  for (const Eigen::Vector3f& p : points) {
    if (crop.Contains(p)) kept.push_back(p);
  }
  return kept;
}

TriangleMesh ClipMesh(const TriangleMesh& mesh, const ModelCrop& crop) {
  if (crop.kind == ModelCrop::Kind::kNone) return mesh;
  const std::vector<HalfSpace> planes = Planes(crop);
  TriangleMesh out;
  std::vector<uint32_t> kept_index(mesh.vertices.size(), UINT32_MAX);
  auto vertex_of_original = [&](uint32_t i) {
    if (kept_index[i] == UINT32_MAX) {
      kept_index[i] = static_cast<uint32_t>(out.vertices.size());
      out.vertices.push_back(mesh.vertices[i]);
    }
    return kept_index[i];
  };
  for (const auto& t : mesh.triangles) {
    Polygon polygon = {mesh.vertices[t[0]].cast<double>(), mesh.vertices[t[1]].cast<double>(),
                       mesh.vertices[t[2]].cast<double>()};
    if (crop.kind == ModelCrop::Kind::kCylinder &&
        !RadiallyInside(crop, (polygon[0] + polygon[1] + polygon[2]) / 3.0)) {
      continue;
    }
    bool whole = true;
    for (const HalfSpace& h : planes) {
      for (const Eigen::Vector3d& p : polygon) whole = whole && h.n.dot(p) <= h.d;
    }
    if (whole) {
      out.triangles.push_back({vertex_of_original(t[0]), vertex_of_original(t[1]), vertex_of_original(t[2])});
      continue;
    }
    for (const HalfSpace& h : planes) {
      polygon = Clip(polygon, h);
      if (polygon.size() < 3) break;
    }
    if (polygon.size() < 3) continue;
    const auto first = static_cast<uint32_t>(out.vertices.size());
    for (const Eigen::Vector3d& p : polygon) out.vertices.push_back(p.cast<float>());
    for (uint32_t k = 1; k + 1 < polygon.size(); ++k) out.triangles.push_back({first, first + k, first + k + 1});
  }
  return out;
}

}  // namespace vscan::service
