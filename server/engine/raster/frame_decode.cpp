#include "raster/frame_decode.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

namespace vscan::raster {
namespace {

constexpr uint32_t kRowsPerTask = 8;

struct RangeSpan {
  double min = std::numeric_limits<double>::infinity();
  double max = 0;
};

float* FloatsOf(std::vector<Eigen::Vector3f>& v) { return v.empty() ? nullptr : v.front().data(); }

// A face id the frame can hold: 0 (nothing) or a face of the scene plus one.
bool Covered(uint32_t id, size_t face_count) { return id != 0 && id <= face_count; }

// Per-scan constants and the per-pixel work. Depth is linearised in double precision, the rest
// is single precision like the ray caster's output.
class Decoder {
 public:
  Decoder(const RenderedFrame& frame, const SceneFaces& faces, const DecodeRequest& r, PointCloud& cloud,
          std::vector<float>& direct_radiance)
      : frame_(frame), faces_(faces), r_(r) {
    radiance_ = direct_radiance.empty() ? nullptr : direct_radiance.data();
    const sensor::PinholeCamera& c = *r.camera;
    for (uint32_t u = 0; u < c.width; ++u) column_x_.push_back(static_cast<float>((u + 0.5 - c.cx) / c.fx));
    for (uint32_t v = 0; v < c.height; ++v) row_y_.push_back(static_cast<float>((v + 0.5 - c.cy) / c.fy));
    rotation_ = r.world_from_sensor.linear().cast<float>();
    origin_ = r.world_from_sensor.translation().cast<float>();
    depth_method_ = r.method == RasterMethod::kDepthBuffer;
    reversed_ = r.depth_format == DepthFormat::kFloat32Reversed;
    range_step_ = (r.planes.far_range - r.planes.near_range) / 65535.0;
    const sensor::Lighting& light = c.lighting;
    colour_intensity_ = static_cast<float>(light.power / Attenuation(light, r.planes.near_range) / 255.0);
    power_ = static_cast<float>(light.power);
    constant_ = static_cast<float>(light.constant);
    linear_ = static_cast<float>(light.linear);
    quadratic_ = static_cast<float>(light.quadratic);
    positions_ = FloatsOf(cloud.positions);
    normals_ = cloud.Has(kFieldNormal) ? FloatsOf(cloud.normals) : nullptr;
    ranges_ = cloud.Has(kFieldRange) ? cloud.ranges.data() : nullptr;
    intensities_ = cloud.Has(kFieldIntensity) ? cloud.intensities.data() : nullptr;
    instance_ids_ = cloud.Has(kFieldInstanceId) ? cloud.instance_ids.data() : nullptr;
    pixels_ = cloud.Has(kFieldPixel) ? cloud.pixels.data() : nullptr;
  }

  // Writes the covered pixels of row v from slot k on.
  void DecodeRow(uint32_t v, size_t k, RangeSpan& span) const {
    const uint32_t width = frame_.width;
    const size_t row = size_t{v} * width;
    const uint32_t* ids = frame_.faces.get() + row;
    const uint32_t* depth = depth_method_ ? frame_.depth.get() + row : nullptr;
    const uint8_t* rgba = depth_method_ ? nullptr : frame_.colour.get() + 4 * row;
    const Eigen::Vector3f* face_normals = faces_.normals.data();
    const uint32_t* face_instances = faces_.instance_ids.data();
    const size_t face_count = faces_.size();
    const float y = row_y_[v];
    const ViewPlanes& p = r_.planes;
    for (uint32_t u = 0; u < width; ++u) {
      const uint32_t id = ids[u];
      if (!Covered(id, face_count)) continue;
      const float x = column_x_[u];
      const float ray_length = std::sqrt(x * x + y * y + 1.0f);
      double z, range;
      if (depth_method_) {
        z = std::clamp(LinearDepth(WindowDepth(depth[u]), p.near, p.far, reversed_), p.near, p.far);
        range = z * ray_length;
      } else {
        const uint8_t* c = rgba + 4 * u;
        range = std::clamp(p.near_range + (c[1] * 256 + c[2]) * range_step_, p.near * ray_length, p.far * ray_length);
        z = range / ray_length;
        if (intensities_ != nullptr) intensities_[k] = c[0] * colour_intensity_;
      }
      const auto t = static_cast<float>(z);  // the ray has z = 1
      Store(Eigen::Vector3f(x * t, y * t, t), face_normals[id - 1], x, y, ray_length, static_cast<float>(range), k);
      if (instance_ids_ != nullptr) instance_ids_[k] = face_instances[id - 1];
      if (pixels_ != nullptr) pixels_[k] = static_cast<uint32_t>(row + u);
      if (radiance_ != nullptr) radiance_[k] = frame_.radiance[row + u];
      span.min = std::min(span.min, range);
      span.max = std::max(span.max, range);
      ++k;
    }
  }

 private:
  double WindowDepth(uint32_t bits) const {
    if (r_.depth_format == DepthFormat::kFixed24) return (bits >> 8) / 16777215.0;
    float d;
    std::memcpy(&d, &bits, sizeof(d));
    return d;
  }

  // Position and normal in the requested frame, range, and (depth method) intensity at slot k.
  void Store(const Eigen::Vector3f& sensor_point, const Eigen::Vector3f& face_normal, float x, float y, float ray_length,
             float range, size_t k) const {
    const Eigen::Matrix3f& r = rotation_;
    Eigen::Vector3f world_normal = face_normal;
    Eigen::Vector3f sensor_normal = r.transpose() * world_normal;
    const float facing = sensor_normal.x() * x + sensor_normal.y() * y + sensor_normal.z();
    if (facing > 0) {
      sensor_normal = -sensor_normal;
      world_normal = -world_normal;
    }
    const Eigen::Vector3f position = r_.sensor_frame ? sensor_point : Eigen::Vector3f(r * sensor_point + origin_);
    const Eigen::Vector3f& normal = r_.sensor_frame ? sensor_normal : world_normal;
    for (int i = 0; i < 3; ++i) positions_[3 * k + i] = position[i];
    if (normals_ != nullptr) {
      for (int i = 0; i < 3; ++i) normals_[3 * k + i] = normal[i];
    }
    if (ranges_ != nullptr) ranges_[k] = range;
    if (intensities_ != nullptr && depth_method_) {
      // sensor::Intensity, inlined: cos(incidence) = |facing| / ray_length.
      intensities_[k] = power_ * std::abs(facing) / (ray_length * (constant_ + (linear_ + quadratic_ * range) * range));
    }
  }

  const RenderedFrame& frame_;
  const SceneFaces& faces_;
  const DecodeRequest& r_;
  std::vector<float> column_x_, row_y_;  // sensor-frame ray (x, y, 1) through each pixel centre
  Eigen::Matrix3f rotation_;             // world_from_sensor
  Eigen::Vector3f origin_;
  bool depth_method_ = true, reversed_ = false;
  double range_step_ = 0;          // colour method: metres per code
  float colour_intensity_ = 0;     // colour method: intensity per unit of R
  float power_ = 1, constant_ = 1, linear_ = 0, quadratic_ = 0;
  float* positions_ = nullptr;
  float* normals_ = nullptr;
  float* ranges_ = nullptr;
  float* intensities_ = nullptr;
  uint32_t* instance_ids_ = nullptr;
  uint32_t* pixels_ = nullptr;
  float* radiance_ = nullptr;
};

}  // namespace

StatusOr<DecodedFrame> DecodeFrame(const RenderedFrame& frame, const SceneFaces& faces, const DecodeRequest& request) {
  DecodedFrame out;
  out.cloud.fields = request.fields | kFieldPosition;
  if (frame.empty()) return out;
  const uint32_t width = frame.width, height = frame.height;
  const size_t face_count = faces.size();

  // Points before each row, so rows fill their own slots in row-major order in parallel.
  std::vector<size_t> first(size_t{height} + 1, 0);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, kRowsPerTask), [&](const tbb::blocked_range<uint32_t>& rows) {
    for (uint32_t v = rows.begin(); v != rows.end(); ++v) {
      const uint32_t* ids = frame.faces.get() + size_t{v} * width;
      first[v + 1] = static_cast<size_t>(std::count_if(ids, ids + width, [&](uint32_t id) { return Covered(id, face_count); }));
    }
  });
  for (uint32_t v = 0; v < height; ++v) first[v + 1] += first[v];
  out.cloud.Resize(first[height]);
  if (frame.radiance != nullptr) out.direct_radiance.resize(first[height]);

  const Decoder decoder(frame, faces, request, out.cloud, out.direct_radiance);
  tbb::combinable<RangeSpan> spans;
  std::atomic<bool> cancelled{false};
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, kRowsPerTask), [&](const tbb::blocked_range<uint32_t>& rows) {
    if (request.cancel != nullptr && request.cancel->load(std::memory_order_relaxed)) {
      cancelled = true;
      return;
    }
    RangeSpan& span = spans.local();
    for (uint32_t v = rows.begin(); v != rows.end(); ++v) decoder.DecodeRow(v, first[v], span);
  });
  if (cancelled) return Cancelled("scan cancelled");
  const RangeSpan all = spans.combine([](const RangeSpan& a, const RangeSpan& b) {
    return RangeSpan{std::min(a.min, b.min), std::max(a.max, b.max)};
  });
  if (out.cloud.size() > 0) {
    out.min_range = all.min;
    out.max_range = all.max;
  }
  return out;
}

}  // namespace vscan::raster
