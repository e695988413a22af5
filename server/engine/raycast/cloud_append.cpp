#include "raycast/cloud_append.h"

#include "raycast/stream_copy.h"

namespace vscan::raycast {
namespace {

// Copies a strip's values row by row to the end of out, which is reserved and never reallocates.
template <typename T>
void AppendField(const T* values, const RowBlock& hits, std::vector<T>& out) {
  for (uint32_t r = 0; r < hits.rows; ++r) {
    const T* row = values + size_t{r} * hits.stride;
    out.insert(out.end(), row, row + hits.count[r]);
  }
}

// Eigen vectors are not trivially copyable, so insert would copy them one by one; resizing
// leaves them uninitialised and one streaming copy per row fills them.
void AppendField(const float* values, const RowBlock& hits, std::vector<Eigen::Vector3f>& out) {
  size_t at = out.size();
  out.resize(at + hits.total());
  for (uint32_t r = 0; r < hits.rows; ++r) {
    StreamCopy(out.data() + at, values + size_t{3} * r * hits.stride, sizeof(Eigen::Vector3f) * hits.count[r]);
    at += hits.count[r];
  }
}

}  // namespace

void AppendRows(const RowBlock& hits, PointCloud& cloud) {
  if (hits.total() == 0) return;
  AppendField(hits.positions, hits, cloud.positions);
  if (cloud.Has(kFieldNormal)) AppendField(hits.normals, hits, cloud.normals);
  if (cloud.Has(kFieldRange)) AppendField(hits.ranges, hits, cloud.ranges);
  if (cloud.Has(kFieldIntensity)) AppendField(hits.intensities, hits, cloud.intensities);
  if (cloud.Has(kFieldInstanceId)) AppendField(hits.instance_ids, hits, cloud.instance_ids);
  if (cloud.Has(kFieldPixel)) AppendField(hits.pixels, hits, cloud.pixels);
  StreamFence();
}

void ReserveForEveryPixel(PointCloud& cloud, size_t n) {
  cloud.positions.reserve(n);
  if (cloud.Has(kFieldNormal)) cloud.normals.reserve(n);
  if (cloud.Has(kFieldRange)) cloud.ranges.reserve(n);
  if (cloud.Has(kFieldIntensity)) cloud.intensities.reserve(n);
  if (cloud.Has(kFieldInstanceId)) cloud.instance_ids.reserve(n);
  if (cloud.Has(kFieldPixel)) cloud.pixels.reserve(n);
}

void TrimExcess(PointCloud& cloud) {
  if (cloud.positions.size() * 2 >= cloud.positions.capacity()) return;
  cloud.positions.shrink_to_fit();
  cloud.normals.shrink_to_fit();
  cloud.ranges.shrink_to_fit();
  cloud.intensities.shrink_to_fit();
  cloud.instance_ids.shrink_to_fit();
  cloud.pixels.shrink_to_fit();
}

}  // namespace vscan::raycast
