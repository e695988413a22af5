#include "raycast/point_queries.h"

#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "geometry/closest_point.h"
#include "raycast/embree_scene.h"

namespace vscan::raycast {
namespace {

constexpr size_t kPointGrain = 512;

struct QueryState {
  RTCScene scene;
  Eigen::Vector3f point;
  float best_dist_sq;
  bool found;
};

Eigen::Vector3f Vertex(const float* vertices, uint32_t index) {
  return {vertices[3 * index], vertices[3 * index + 1], vertices[3 * index + 2]};
}

// Embree calls this for each triangle whose bounds meet the query sphere; shrinking the radius
// prunes the rest of the traversal.
bool TriangleQuery(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<QueryState*>(args->userPtr);
  RTCGeometry geometry = rtcGetGeometry(state->scene, args->geomID);
  const auto* vertices = static_cast<const float*>(rtcGetGeometryBufferData(geometry, RTC_BUFFER_TYPE_VERTEX, 0));
  const auto* indices = static_cast<const uint32_t*>(rtcGetGeometryBufferData(geometry, RTC_BUFFER_TYPE_INDEX, 0));
  const uint32_t* tri = indices + 3 * size_t{args->primID};
  const Eigen::Vector3f closest = ClosestPointOnTriangle(state->point, Vertex(vertices, tri[0]),
                                                         Vertex(vertices, tri[1]), Vertex(vertices, tri[2]));
  const float dist_sq = (closest - state->point).squaredNorm();
  if (dist_sq >= state->best_dist_sq) return false;
  state->best_dist_sq = dist_sq;
  state->found = true;
  args->query->radius = std::sqrt(dist_sq);
  return true;
}

}  // namespace

Eigen::Vector3f ClosestPointOnTriangle(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                                       const Eigen::Vector3f& c) {
  return geometry::ClosestPointOnTriangle<float>(p, a, b, c);
}

std::vector<float> DistancesToSurface(const RaycastScene& scene, std::span<const Eigen::Vector3f> points,
                                      float max_distance) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  std::vector<float> distances(points.size(), kInf);
  const RTCScene rtc = EmbreeOf(scene).scene;
  if (scene.triangle_count() == 0) return distances;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), kPointGrain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3f& p = points[i];
      if (!p.allFinite()) continue;
      RTCPointQuery query{};
      query.x = p.x();
      query.y = p.y();
      query.z = p.z();
      query.radius = max_distance;
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      QueryState state{rtc, p, std::isinf(max_distance) ? kInf : max_distance * max_distance, false};
      rtcPointQuery(rtc, &query, &context, TriangleQuery, &state);
      if (state.found) distances[i] = std::sqrt(state.best_dist_sq);
    }
  });
  return distances;
}

}  // namespace vscan::raycast
