#include "packet_loop.h"

#include <algorithm>
#include <cstring>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace vscan::bench {

PacketLoop::PacketLoop(RTCScene scene, const sensor::PinholeCamera& camera, const Pose3& world_from_sensor)
    : scene_(scene),
      camera_(camera),
      origin_(world_from_sensor.translation().cast<float>()),
      rotation_(world_from_sensor.linear().cast<float>()) {
  for (uint32_t v = 0; v < camera.height; ++v) row_y_.push_back(camera.RayThroughPixel(0, v).y());
  for (uint32_t u0 = 0; u0 < camera.width; u0 += 4) {
    for (uint32_t i = 0; i < 16; ++i) {
      packet_x_.push_back(camera.RayThroughPixel(u0 + i % 4, 0).x());
    }
  }
}

uint64_t PacketLoop::Frame() const {
  const auto& cam = camera_;
  const Eigen::Vector3f o = origin_;
  const Eigen::Matrix3f& r = rotation_;
  const uint32_t strips = (cam.height + 3) / 4;
  return tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(0, strips), uint64_t{0},
      [&](const tbb::blocked_range<uint32_t>& range, uint64_t hits) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        RTCRayHit16 packet;
        for (uint32_t i = 0; i < 16; ++i) {
          packet.ray.org_x[i] = o.x();
          packet.ray.org_y[i] = o.y();
          packet.ray.org_z[i] = o.z();
          packet.ray.tnear[i] = static_cast<float>(cam.near);
          packet.ray.time[i] = 0;
          packet.ray.mask[i] = 0xFFFFFFFFu;
          packet.ray.id[i] = i;
          packet.ray.flags[i] = 0;
        }
        alignas(64) int valid[16];
        alignas(64) float x[16], y[16];
        for (uint32_t s = range.begin(); s != range.end(); ++s) {
          for (uint32_t i = 0; i < 16; ++i) {
            y[i] = row_y_[std::min(4 * s + i / 4, cam.height - 1)];
            valid[i] = 4 * s + i / 4 < cam.height ? -1 : 0;
          }
          for (uint32_t u0 = 0; u0 < cam.width; u0 += 4) {
            // Packets never straddle the right border: the width is a multiple of 4.
            std::memcpy(x, packet_x_.data() + 4 * u0, sizeof x);
            for (uint32_t i = 0; i < 16; ++i) {
              packet.ray.dir_x[i] = r(0, 0) * x[i] + r(0, 1) * y[i] + r(0, 2);
              packet.ray.dir_y[i] = r(1, 0) * x[i] + r(1, 1) * y[i] + r(1, 2);
              packet.ray.dir_z[i] = r(2, 0) * x[i] + r(2, 1) * y[i] + r(2, 2);
              packet.ray.tfar[i] = static_cast<float>(cam.far);
              packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, scene_, &context, &packet);
            for (uint32_t i = 0; i < 16; ++i) hits += packet.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
          }
        }
        return hits;
      },
      std::plus<>());
}

}  // namespace vscan::bench
