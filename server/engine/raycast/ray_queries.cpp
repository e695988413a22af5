#include "raycast/ray_queries.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "raycast/embree_scene.h"
#include "raycast/ray_bounds.h"

namespace vscan::raycast {
namespace {

constexpr size_t kRayGrain = 1024;
constexpr size_t kOcclusionLanes = 16;

RTCRay MakeRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near, float t_far) {
  RTCRay ray{};
  ray.org_x = origin.x();
  ray.org_y = origin.y();
  ray.org_z = origin.z();
  ray.dir_x = direction.x();
  ray.dir_y = direction.y();
  ray.dir_z = direction.z();
  ray.tnear = t_near;
  ray.tfar = t_far;
  ray.mask = ~0u;
  return ray;
}

void SetLane(RTCRay16& packet, size_t lane, const RTCRay& ray) {
  packet.org_x[lane] = ray.org_x;
  packet.org_y[lane] = ray.org_y;
  packet.org_z[lane] = ray.org_z;
  packet.dir_x[lane] = ray.dir_x;
  packet.dir_y[lane] = ray.dir_y;
  packet.dir_z[lane] = ray.dir_z;
  packet.tnear[lane] = ray.tnear;
  packet.tfar[lane] = ray.tfar;
  packet.time[lane] = 0;
  packet.mask[lane] = ray.mask;
  packet.id[lane] = 0;
  packet.flags[lane] = 0;
}

RayHit IntersectWith(const RaycastScene& scene, RTCScene rtc, RTCIntersectContext& context,
                     const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near, float t_far) {
  RayHit out;
  if (!EmbreeAcceptsRay(origin, direction, t_near, t_far)) return out;  // a miss
  RTCRayHit query{};
  query.ray = MakeRay(origin, direction, t_near, t_far);
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(rtc, &context, &query);
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  out.hit = true;
  out.distance = query.ray.tfar;
  Eigen::Vector3f n(query.hit.Ng_x, query.hit.Ng_y, query.hit.Ng_z);
  const float length = n.norm();
  n = length > 0 ? Eigen::Vector3f(n / length) : Eigen::Vector3f(-direction);
  out.normal = n.dot(direction) > 0 ? Eigen::Vector3f(-n) : n;
  out.instance_id = scene.InstanceOfGeometry(query.hit.geomID);
  return out;
}

}  // namespace

RayHit IntersectRay(const RaycastScene& scene, const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                    float t_near, float t_far) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  return IntersectWith(scene, EmbreeOf(scene).scene, context, origin, direction, t_near, t_far);
}

bool SegmentOccluded(const RaycastScene& scene, const Eigen::Vector3f& from, const Eigen::Vector3f& to, float margin) {
  const Eigen::Vector3f d = to - from;
  const float length = d.norm();
  if (!(length > 2 * margin) || !EmbreeAcceptsRay(from, d / length, margin, length - margin)) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = MakeRay(from, d / length, margin, length - margin);
  rtcOccluded1(EmbreeOf(scene).scene, &context, &ray);
  return std::isinf(ray.tfar) && ray.tfar < 0;
}

std::vector<RayHit> IntersectRays(const RaycastScene& scene, std::span<const Eigen::Vector3f> origins,
                                  std::span<const Eigen::Vector3f> directions, float t_near, float t_far) {
  std::vector<RayHit> hits(origins.size());
  const RTCScene rtc = EmbreeOf(scene).scene;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, origins.size(), kRayGrain), [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = r.begin(); i != r.end(); ++i) {
      hits[i] = IntersectWith(scene, rtc, context, origins[i], directions[i], t_near, t_far);
    }
  });
  return hits;
}

std::vector<uint8_t> OccludedSegments(const RaycastScene& scene, std::span<const Eigen::Vector3f> from,
                                      std::span<const Eigen::Vector3f> to, float relative_margin,
                                      float min_margin) {
  std::vector<uint8_t> occluded(from.size(), 0);
  const RTCScene rtc = EmbreeOf(scene).scene;
  // Packets of neighbouring segments: a scan's segments come in pixel order from one emitter, so a
  // packet's rays run nearly side by side and Embree traverses them together.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, from.size(), kRayGrain), [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRay16 packet;
    alignas(64) int valid[kOcclusionLanes];
    for (size_t first = r.begin(); first < r.end(); first += kOcclusionLanes) {
      const size_t lanes = std::min(kOcclusionLanes, r.end() - first);
      bool any = false;
      for (size_t lane = 0; lane < kOcclusionLanes; ++lane) {
        valid[lane] = 0;
        if (lane >= lanes) continue;
        const size_t i = first + lane;
        const Eigen::Vector3f d = to[i] - from[i];
        const float length = d.norm();
        const float margin = std::max(min_margin, relative_margin * length);
        if (!(length > 2 * margin) || !EmbreeAcceptsRay(from[i], d / length, margin, length - margin)) continue;
        SetLane(packet, lane, MakeRay(from[i], d / length, margin, length - margin));
        valid[lane] = -1;
        any = true;
      }
      if (!any) continue;
      rtcOccluded16(valid, rtc, &context, &packet);
      for (size_t lane = 0; lane < lanes; ++lane) {
        // Embree sets an occluded ray's tfar to -inf.
        if (valid[lane] != 0) occluded[first + lane] = std::isinf(packet.tfar[lane]) && packet.tfar[lane] < 0 ? 1 : 0;
      }
    }
  });
  return occluded;
}

}  // namespace vscan::raycast
