#include "vscan/common/point_chunks.h"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <iterator>
#include <string>

namespace vscan {
namespace {

static_assert(std::endian::native == std::endian::little, "the wire format is little-endian");

template <typename T>
void CopyOut(const std::vector<T>& src, size_t begin, size_t count, std::string* dst) {
  dst->resize(count * sizeof(T));
  if (count) std::memcpy(dst->data(), src.data() + begin, count * sizeof(T));
}

// Reads T values out of bytes with no alignment for T; lets a vector grow straight from the
// wire bytes instead of zero-filling new elements and then overwriting them.
template <typename T>
class LoadIterator {
 public:
  using iterator_category = std::random_access_iterator_tag;
  using value_type = T;
  using difference_type = std::ptrdiff_t;
  using pointer = const T*;
  using reference = T;

  explicit LoadIterator(const char* p) : p_(p) {}
  T operator*() const {
    T v;
    std::memcpy(static_cast<void*>(&v), p_, sizeof(T));
    return v;
  }
  LoadIterator& operator++() {
    p_ += sizeof(T);
    return *this;
  }
  LoadIterator operator++(int) {
    LoadIterator old = *this;
    p_ += sizeof(T);
    return old;
  }
  LoadIterator& operator--() {
    p_ -= sizeof(T);
    return *this;
  }
  LoadIterator& operator+=(difference_type n) {
    p_ += n * static_cast<difference_type>(sizeof(T));
    return *this;
  }
  LoadIterator operator+(difference_type n) const { return LoadIterator(*this) += n; }
  difference_type operator-(const LoadIterator& other) const {
    return (p_ - other.p_) / static_cast<difference_type>(sizeof(T));
  }
  bool operator==(const LoadIterator& other) const { return p_ == other.p_; }
  bool operator!=(const LoadIterator& other) const { return p_ != other.p_; }

 private:
  const char* p_;
};

Status CheckSize(const std::string& src, size_t count, size_t value_bytes, const char* name) {
  if (src.size() != count * value_bytes) {
    return InvalidArgument(std::string("chunk.") + name + ": expected " + std::to_string(count * value_bytes) +
                           " bytes, got " + std::to_string(src.size()));
  }
  return Status::Ok();
}

template <typename T>
Status CopyIn(const std::string& src, size_t count, const char* name, std::vector<T>* dst) {
  RETURN_IF_ERROR(CheckSize(src, count, sizeof(T), name));
  dst->insert(dst->end(), LoadIterator<T>(src.data()), LoadIterator<T>(src.data() + src.size()));
  return Status::Ok();
}

}  // namespace

size_t PointsPerChunk(uint32_t fields, size_t chunk_bytes) {
  PointCloud probe;
  probe.fields = fields;
  return std::max<size_t>(1, chunk_bytes / probe.BytesPerPoint());
}

void PackChunk(const PointCloud& cloud, size_t begin, size_t count, uint32_t index, v1::PointChunk* out) {
  out->set_index(index);
  out->set_count(static_cast<uint32_t>(count));
  CopyOut(cloud.positions, begin, count, out->mutable_positions());
  if (cloud.Has(kFieldNormal)) CopyOut(cloud.normals, begin, count, out->mutable_normals());
  if (cloud.Has(kFieldRange)) CopyOut(cloud.ranges, begin, count, out->mutable_ranges());
  if (cloud.Has(kFieldIntensity)) CopyOut(cloud.intensities, begin, count, out->mutable_intensities());
  if (cloud.Has(kFieldInstanceId)) CopyOut(cloud.instance_ids, begin, count, out->mutable_instance_ids());
  if (cloud.Has(kFieldPixel)) CopyOut(cloud.pixels, begin, count, out->mutable_pixels());
  if (cloud.Has(kFieldCleanPosition)) CopyOut(cloud.clean_positions, begin, count, out->mutable_clean_positions());
  if (cloud.Has(kFieldIncidence)) CopyOut(cloud.incidence_angles, begin, count, out->mutable_incidence_angles());
  if (cloud.Has(kFieldStatus)) CopyOut(cloud.statuses, begin, count, out->mutable_statuses());
  if (cloud.Has(kFieldEstimatedNormal))
    CopyOut(cloud.estimated_normals, begin, count, out->mutable_estimated_normals());
}

Status AppendChunk(const v1::PointChunk& chunk, PointCloud* cloud) {
  const size_t n = chunk.count();
  RETURN_IF_ERROR(CopyIn(chunk.positions(), n, "positions", &cloud->positions));
  if (cloud->Has(kFieldNormal)) RETURN_IF_ERROR(CopyIn(chunk.normals(), n, "normals", &cloud->normals));
  if (cloud->Has(kFieldRange)) RETURN_IF_ERROR(CopyIn(chunk.ranges(), n, "ranges", &cloud->ranges));
  if (cloud->Has(kFieldIntensity))
    RETURN_IF_ERROR(CopyIn(chunk.intensities(), n, "intensities", &cloud->intensities));
  if (cloud->Has(kFieldInstanceId))
    RETURN_IF_ERROR(CopyIn(chunk.instance_ids(), n, "instance_ids", &cloud->instance_ids));
  if (cloud->Has(kFieldPixel)) RETURN_IF_ERROR(CopyIn(chunk.pixels(), n, "pixels", &cloud->pixels));
  if (cloud->Has(kFieldCleanPosition))
    RETURN_IF_ERROR(CopyIn(chunk.clean_positions(), n, "clean_positions", &cloud->clean_positions));
  if (cloud->Has(kFieldIncidence))
    RETURN_IF_ERROR(CopyIn(chunk.incidence_angles(), n, "incidence_angles", &cloud->incidence_angles));
  if (cloud->Has(kFieldStatus)) RETURN_IF_ERROR(CopyIn(chunk.statuses(), n, "statuses", &cloud->statuses));
  if (cloud->Has(kFieldEstimatedNormal))
    RETURN_IF_ERROR(CopyIn(chunk.estimated_normals(), n, "estimated_normals", &cloud->estimated_normals));
  return Status::Ok();
}

Status CheckChunk(const v1::PointChunk& chunk, uint32_t fields) {
  const size_t n = chunk.count();
  RETURN_IF_ERROR(CheckSize(chunk.positions(), n, 12, "positions"));
  if (fields & kFieldNormal) RETURN_IF_ERROR(CheckSize(chunk.normals(), n, 12, "normals"));
  if (fields & kFieldRange) RETURN_IF_ERROR(CheckSize(chunk.ranges(), n, 4, "ranges"));
  if (fields & kFieldIntensity) RETURN_IF_ERROR(CheckSize(chunk.intensities(), n, 4, "intensities"));
  if (fields & kFieldInstanceId) RETURN_IF_ERROR(CheckSize(chunk.instance_ids(), n, 4, "instance_ids"));
  if (fields & kFieldPixel) RETURN_IF_ERROR(CheckSize(chunk.pixels(), n, 4, "pixels"));
  if (fields & kFieldCleanPosition) RETURN_IF_ERROR(CheckSize(chunk.clean_positions(), n, 12, "clean_positions"));
  if (fields & kFieldIncidence) RETURN_IF_ERROR(CheckSize(chunk.incidence_angles(), n, 4, "incidence_angles"));
  if (fields & kFieldStatus) RETURN_IF_ERROR(CheckSize(chunk.statuses(), n, 1, "statuses"));
  if (fields & kFieldEstimatedNormal) {
    RETURN_IF_ERROR(CheckSize(chunk.estimated_normals(), n, 12, "estimated_normals"));
  }
  return Status::Ok();
}

}  // namespace vscan
