#include "reconstruction/tsdf_integration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "reconstruction/stop_flag.h"

namespace vscan::reconstruction {
namespace {

// One image's projection, in float for the inner loops.
struct View {
  const RangeImage* image;
  Eigen::Matrix3f sensor_from_world_rot;
  Eigen::Vector3f sensor_from_world_t;
  Eigen::Matrix3f world_from_sensor_rot;
  Eigen::Vector3f origin;
  float fx, fy, cx, cy;
  int width, height;
  float near, far;

  explicit View(const RangeImage& im)
      : image(&im),
        sensor_from_world_rot(im.world_from_sensor.inverse().linear().cast<float>()),
        sensor_from_world_t(im.world_from_sensor.inverse().translation().cast<float>()),
        world_from_sensor_rot(im.world_from_sensor.linear().cast<float>()),
        origin(im.world_from_sensor.translation().cast<float>()),
        fx(static_cast<float>(im.camera.fx)),
        fy(static_cast<float>(im.camera.fy)),
        cx(static_cast<float>(im.camera.cx)),
        cy(static_cast<float>(im.camera.cy)),
        width(static_cast<int>(im.camera.width)),
        height(static_cast<int>(im.camera.height)),
        near(static_cast<float>(im.camera.near)),
        far(static_cast<float>(im.camera.far)) {}

  float Depth(int u, int v) const { return image->depth[static_cast<size_t>(v) * width + u]; }
  float Weight(int u, int v) const { return weights[static_cast<size_t>(v) * width + u]; }
  Eigen::Vector3f Point(int u, int v) const {
    return Depth(u, v) * Eigen::Vector3f((u + 0.5f - cx) / fx, (v + 0.5f - cy) / fy, 1.0f);
  }

  // Per pixel, the cosine of the angle between its ray and the surface normal.
  std::vector<float> weights;
};

bool Valid(float d) { return d > 0 && std::isfinite(d); }

// A pixel's weight is the cosine of its incidence angle: it turns distances along the ray into
// distances to the surface, and it falls towards the grazing edges of what a view sees, where the
// depth behind a silhouette would otherwise pull the fused surface outwards.
constexpr float kMinWeight = 0.05f;
// How far behind a surface, along the ray and in truncations, a voxel still takes its distance.
constexpr float kBehindLimit = 3.0f;

// The surface tangent along one image axis at (u, v) from the neighbours on that axis that saw the
// same surface (depth step below max_step); zero when neither did.
Eigen::Vector3f Tangent(const View& view, int u, int v, int du, int dv, float max_step) {
  const float d = view.Depth(u, v);
  const auto usable = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < view.width && y < view.height && Valid(view.Depth(x, y)) &&
           std::abs(view.Depth(x, y) - d) <= max_step;
  };
  const bool next = usable(u + du, v + dv), prev = usable(u - du, v - dv);
  if (next && prev) return view.Point(u + du, v + dv) - view.Point(u - du, v - dv);
  if (next) return view.Point(u + du, v + dv) - view.Point(u, v);
  if (prev) return view.Point(u, v) - view.Point(u - du, v - dv);
  return Eigen::Vector3f::Zero();
}

void ComputeWeights(View& view, float max_step) {
  view.weights.assign(static_cast<size_t>(view.width) * view.height, 0.0f);
  tbb::parallel_for(tbb::blocked_range<int>(0, view.height, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v != rows.end(); ++v) {
      for (int u = 0; u < view.width; ++u) {
        if (!Valid(view.Depth(u, v))) continue;
        const Eigen::Vector3f n = Tangent(view, u, v, 1, 0, max_step).cross(Tangent(view, u, v, 0, 1, max_step));
        const Eigen::Vector3f ray = view.Point(u, v).normalized();
        const float norm = n.norm();
        const float cosine = norm > 0 ? std::abs(n.dot(ray)) / norm : kMinWeight;
        view.weights[static_cast<size_t>(v) * view.width + u] = std::max(cosine, kMinWeight);
      }
    }
  });
}

int FloorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// Collects block keys, skipping keys seen recently: neighbouring pixels mostly touch the same blocks.
class KeyCollector {
 public:
  void Add(uint64_t key) {
    uint64_t& slot = recent_[(key * 0x9e3779b97f4a7c15ull) >> 52];
    if (slot == key + 1) return;
    slot = key + 1;
    keys_.push_back(key);
  }
  std::vector<uint64_t>& keys() { return keys_; }

 private:
  std::array<uint64_t, 4096> recent_{};
  std::vector<uint64_t> keys_;
};

// The blocks holding the 8 voxels around q (those marching cubes reads there); false when q is
// beyond the grid's range.
bool AddBlocksAround(const Eigen::Vector3f& q, float inv_voxel, KeyCollector& out) {
  const Eigen::Vector3f g = q * inv_voxel;
  constexpr float kLimit = static_cast<float>(VoxelBlocks::kCoordLimit - 1) * VoxelBlocks::kSide;
  if (!g.allFinite() || (g.array().abs() >= kLimit).any()) return false;
  Eigen::Vector3i lo, hi;
  for (int a = 0; a < 3; ++a) {
    const int f = static_cast<int>(std::floor(g[a]));
    lo[a] = FloorDiv(f, VoxelBlocks::kSide);
    hi[a] = FloorDiv(f + 1, VoxelBlocks::kSide);
  }
  for (int z = lo.z(); z <= hi.z(); ++z) {
    for (int y = lo.y(); y <= hi.y(); ++y) {
      for (int x = lo.x(); x <= hi.x(); ++x) out.Add(VoxelBlocks::Key({x, y, z}));
    }
  }
  return true;
}

// Keys of every block within the truncation band of any pixel's surface point, sorted and unique.
std::vector<uint64_t> TouchedBlocks(std::span<const View> views, float voxel, float truncation,
                                    const std::atomic<bool>* cancel) {
  tbb::enumerable_thread_specific<KeyCollector> collectors;
  const float inv_voxel = 1.0f / voxel;
  const int steps = static_cast<int>(std::ceil(truncation / voxel));
  const float step = truncation / static_cast<float>(steps);
  for (const View& view : views) {
    tbb::parallel_for(tbb::blocked_range<int>(0, view.height, 8), [&](const tbb::blocked_range<int>& rows) {
      if (Stopped(cancel)) return;
      KeyCollector& out = collectors.local();
      for (int v = rows.begin(); v != rows.end(); ++v) {
        for (int u = 0; u < view.width; ++u) {
          const float d = view.Depth(u, v);
          if (!Valid(d)) continue;
          const Eigen::Vector3f ray((u + 0.5f - view.cx) / view.fx, (v + 0.5f - view.cy) / view.fy, 1.0f);
          const Eigen::Vector3f surface = view.world_from_sensor_rot * (d * ray) + view.origin;
          const Eigen::Vector3f dir = view.world_from_sensor_rot * ray.normalized();
          for (int s = -steps; s <= steps; ++s) AddBlocksAround(surface + (s * step) * dir, inv_voxel, out);
        }
      }
    });
  }
  std::vector<uint64_t> keys;
  for (KeyCollector& c : collectors) keys.insert(keys.end(), c.keys().begin(), c.keys().end());
  tbb::parallel_sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// The depth seen at continuous pixel coordinates (px, py): bilinear between the four nearest pixel
// centres when all saw the same surface (spread below max_spread), else the nearest pixel's depth;
// 0 when the pixel saw nothing, -1 off the image. weight gets the nearest pixel's weight.
float SampleDepth(const View& view, float px, float py, float max_spread, float& weight) {
  const int u = static_cast<int>(std::floor(px));
  const int v = static_cast<int>(std::floor(py));
  if (u < 0 || v < 0 || u >= view.width || v >= view.height) return -1;
  weight = view.Weight(u, v);
  const float nearest = view.Depth(u, v);
  const float fu = px - 0.5f, fv = py - 0.5f;
  const int u0 = static_cast<int>(std::floor(fu)), v0 = static_cast<int>(std::floor(fv));
  if (u0 < 0 || v0 < 0 || u0 + 1 >= view.width || v0 + 1 >= view.height) return nearest;
  const float d00 = view.Depth(u0, v0), d10 = view.Depth(u0 + 1, v0);
  const float d01 = view.Depth(u0, v0 + 1), d11 = view.Depth(u0 + 1, v0 + 1);
  if (!Valid(d00) || !Valid(d10) || !Valid(d01) || !Valid(d11)) return nearest;
  const float lo = std::min({d00, d10, d01, d11}), hi = std::max({d00, d10, d01, d11});
  if (hi - lo > max_spread) return nearest;
  const float a = fu - static_cast<float>(u0), b = fv - static_cast<float>(v0);
  return (1 - b) * ((1 - a) * d00 + a * d10) + b * ((1 - a) * d01 + a * d11);
}

void IntegrateBlock(VoxelBlocks& grid, size_t b, std::span<const View> views, float truncation, bool carve) {
  const float voxel = grid.voxel_size();
  constexpr int kSide = VoxelBlocks::kSide;
  const Eigen::Vector3f origin = (grid.block_coord(b) * kSide).cast<float>() * voxel;
  const Eigen::Vector3f centre = origin + Eigen::Vector3f::Constant(0.5f * (kSide - 1) * voxel);
  const float radius = 0.5f * std::sqrt(3.0f) * kSide * voxel;
  TsdfVoxel* voxels = grid.block(b);
  for (const View& view : views) {
    // Skip images the block cannot appear in: behind the sensor or projected off the image.
    const Eigen::Vector3f c = view.sensor_from_world_rot * centre + view.sensor_from_world_t;
    if (c.z() + radius <= 0) continue;
    if (c.z() > radius) {
      const float margin_u = view.fx * radius / (c.z() - radius), margin_v = view.fy * radius / (c.z() - radius);
      const float pu = view.fx * c.x() / c.z() + view.cx, pv = view.fy * c.y() / c.z() + view.cy;
      if (pu < -margin_u || pv < -margin_v || pu > view.width + margin_u || pv > view.height + margin_v) continue;
    }
    const Eigen::Vector3f base = view.sensor_from_world_rot * origin + view.sensor_from_world_t;
    const Eigen::Vector3f dx = view.sensor_from_world_rot.col(0) * voxel;
    const Eigen::Vector3f dy = view.sensor_from_world_rot.col(1) * voxel;
    const Eigen::Vector3f dz = view.sensor_from_world_rot.col(2) * voxel;
    for (int z = 0; z < kSide; ++z) {
      for (int y = 0; y < kSide; ++y) {
        Eigen::Vector3f p = base + static_cast<float>(y) * dy + static_cast<float>(z) * dz;
        for (int x = 0; x < kSide; ++x, p += dx) {
          if (p.z() <= 0) continue;
          const float inv_z = 1.0f / p.z();
          float weight = 0;
          const float px = view.fx * p.x() * inv_z + view.cx, py = view.fy * p.y() * inv_z + view.cy;
          const float d = SampleDepth(view, px, py, 0.5f * truncation, weight);
          float sdf;
          if (Valid(d)) {
            // Depth difference -> distance along the ray -> distance to the pixel's tangent plane,
            // trusted only up to a few truncations behind the surface along the ray.
            const float along_ray = (d - p.z()) * (p.norm() * inv_z);
            sdf = along_ray * weight;
            if (sdf < -truncation || along_ray < -kBehindLimit * truncation) continue;
          } else if (d == 0 && carve && p.z() >= view.near && p.z() <= view.far) {
            // The ray through this pixel met nothing in range: the voxel is in free space.
            sdf = truncation;
            weight = kMinWeight;
          } else {
            continue;
          }
          TsdfVoxel& voxel_state = voxels[VoxelBlocks::Local(x, y, z)];
          if (Valid(d) && std::abs(sdf) <= voxel) voxel_state.near_surface = 1;
          const float w = voxel_state.weight;
          voxel_state.sdf = (voxel_state.sdf * w + weight * std::min(sdf, truncation)) / (w + weight);
          voxel_state.weight = w + weight;
        }
      }
    }
  }
}

}  // namespace

StatusOr<VoxelBlocks> IntegrateRangeImages(std::span<const RangeImage> images, const TsdfOptions& options,
                                           const std::atomic<bool>* cancel) {
  if (!(options.voxel_size > 0) || !std::isfinite(options.voxel_size)) {
    return InvalidArgument("tsdf.voxel_size: must be finite and positive");
  }
  if (!(options.truncation_voxels >= 1 && options.truncation_voxels < VoxelBlocks::kSide)) {
    return InvalidArgument("tsdf.truncation_voxels: must lie in [1, 8)");
  }
  std::vector<View> views;
  views.reserve(images.size());
  for (size_t i = 0; i < images.size(); ++i) {
    RETURN_IF_ERROR(ValidateRangeImage(images[i], "images[" + std::to_string(i) + "]"));
    views.emplace_back(images[i]);
  }
  const float truncation = options.truncation_voxels * options.voxel_size;
  for (View& view : views) {
    ComputeWeights(view, truncation);
  }
  std::vector<uint64_t> keys = TouchedBlocks(views, options.voxel_size, truncation, cancel);
  if (Stopped(cancel)) return Cancelled("tsdf: stopped");
  const uint64_t block_bytes = sizeof(TsdfVoxel) * VoxelBlocks::kVoxels + sizeof(Eigen::Vector3i) + 32;
  if (options.max_block_bytes > 0 && keys.size() * block_bytes > options.max_block_bytes) {
    return ResourceExhausted("tsdf.voxel_size", "a voxel of " + std::to_string(options.voxel_size * 1e3) +
                                                    " mm needs " + std::to_string(keys.size()) + " blocks (" +
                                                    std::to_string((keys.size() * block_bytes) >> 20) +
                                                    " MiB), more than the " +
                                                    std::to_string(options.max_block_bytes >> 20) +
                                                    " MiB allowed; choose a larger voxel");
  }
  VoxelBlocks grid(options.voxel_size);
  if (!grid.Allocate(keys, cancel)) return Cancelled("tsdf: stopped");
  keys = {};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, grid.block_count(), 4), [&](const tbb::blocked_range<size_t>& r) {
    if (Stopped(cancel)) return;
    for (size_t b = r.begin(); b != r.end(); ++b) IntegrateBlock(grid, b, views, truncation, options.carve_empty_pixels);
  });
  if (Stopped(cancel)) return Cancelled("tsdf: stopped");
  return grid;
}

}  // namespace vscan::reconstruction
