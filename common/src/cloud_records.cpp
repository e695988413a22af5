#include "cloud_records.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <string_view>
#include <utility>

namespace vscan::cloud_records {
namespace {

static_assert(std::endian::native == std::endian::little, "records are read as native little-endian");

template <typename T>
double Load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

double LoadScalar(const char* p, ScalarType type) {
  switch (type) {
    case ScalarType::kInt8: return Load<int8_t>(p);
    case ScalarType::kUint8: return Load<uint8_t>(p);
    case ScalarType::kInt16: return Load<int16_t>(p);
    case ScalarType::kUint16: return Load<uint16_t>(p);
    case ScalarType::kInt32: return Load<int32_t>(p);
    case ScalarType::kUint32: return Load<uint32_t>(p);
    case ScalarType::kInt64: return Load<int64_t>(p);
    case ScalarType::kUint64: return Load<uint64_t>(p);
    case ScalarType::kFloat32: return Load<float>(p);
    case ScalarType::kFloat64: return Load<double>(p);
  }
  return 0;
}

using Property = const RecordProperty*;

// The first property called by one of `names`, or null.
Property Find(const RecordLayout& layout, std::initializer_list<std::string_view> names) {
  for (const std::string_view name : names) {
    for (const RecordProperty& p : layout.properties) {
      if (p.name == name) return &p;
    }
  }
  return nullptr;
}

// A three-component field, present only when all three components are.
struct Vec3 {
  std::array<Property, 3> parts = {};
  explicit operator bool() const { return parts[0] && parts[1] && parts[2]; }
};

Vec3 FindVec3(const RecordLayout& layout, std::initializer_list<std::string_view> x,
              std::initializer_list<std::string_view> y, std::initializer_list<std::string_view> z) {
  return {{Find(layout, x), Find(layout, y), Find(layout, z)}};
}

// Where each PointCloud field sits in a record, under the names WritePly and WritePcd use.
struct FieldMap {
  Vec3 position, normal, clean, estimated;
  Property range, intensity, instance, pixel, incidence, status;

  explicit FieldMap(const RecordLayout& l)
      : position(FindVec3(l, {"x"}, {"y"}, {"z"})),
        normal(FindVec3(l, {"nx", "normal_x"}, {"ny", "normal_y"}, {"nz", "normal_z"})),
        clean(FindVec3(l, {"clean_x"}, {"clean_y"}, {"clean_z"})),
        estimated(FindVec3(l, {"enx", "est_normal_x"}, {"eny", "est_normal_y"}, {"enz", "est_normal_z"})),
        range(Find(l, {"range"})),
        intensity(Find(l, {"intensity"})),
        instance(Find(l, {"instance", "instance_id"})),
        pixel(Find(l, {"pixel"})),
        incidence(Find(l, {"incidence"})),
        status(Find(l, {"status"})) {}

  uint32_t Fields() const {
    uint32_t fields = kFieldPosition;
    if (normal) fields |= kFieldNormal;
    if (range) fields |= kFieldRange;
    if (intensity) fields |= kFieldIntensity;
    if (instance) fields |= kFieldInstanceId;
    if (pixel) fields |= kFieldPixel;
    if (clean) fields |= kFieldCleanPosition;
    if (incidence) fields |= kFieldIncidence;
    if (status) fields |= kFieldStatus;
    if (estimated) fields |= kFieldEstimatedNormal;
    return fields;
  }

  void Decode(const char* record, size_t i, PointCloud& cloud) const {
    const auto f = [&](Property p) { return static_cast<float>(LoadScalar(record + p->offset, p->type)); };
    const auto v = [&](const Vec3& p) { return Eigen::Vector3f(f(p.parts[0]), f(p.parts[1]), f(p.parts[2])); };
    // Converting an out-of-range double to an integer is undefined; such foreign values read as 0.
    // vscan writes its uint32 fields as int32 (what Open3D reads); the bits are the value.
    const auto u = [&](Property p) {
      if (p->type == ScalarType::kInt32) {
        int32_t bits;
        std::memcpy(&bits, record + p->offset, 4);
        return static_cast<uint32_t>(bits);
      }
      const double value = LoadScalar(record + p->offset, p->type);
      return value >= 0 && value <= std::numeric_limits<uint32_t>::max() ? static_cast<uint32_t>(value) : 0u;
    };
    cloud.positions[i] = v(position);
    if (normal) cloud.normals[i] = v(normal);
    if (range) cloud.ranges[i] = f(range);
    if (intensity) cloud.intensities[i] = f(intensity);
    if (instance) cloud.instance_ids[i] = u(instance);
    if (pixel) cloud.pixels[i] = u(pixel);
    if (clean) cloud.clean_positions[i] = v(clean);
    if (incidence) cloud.incidence_angles[i] = f(incidence);
    if (status) cloud.statuses[i] = static_cast<uint8_t>(std::min(u(status), 255u));
    if (estimated) cloud.estimated_normals[i] = v(estimated);
  }
};

}  // namespace

size_t ScalarSize(ScalarType type) {
  switch (type) {
    case ScalarType::kInt8:
    case ScalarType::kUint8: return 1;
    case ScalarType::kInt16:
    case ScalarType::kUint16: return 2;
    case ScalarType::kInt32:
    case ScalarType::kUint32:
    case ScalarType::kFloat32: return 4;
    case ScalarType::kInt64:
    case ScalarType::kUint64:
    case ScalarType::kFloat64: return 8;
  }
  return 0;
}

void RecordLayout::Add(std::string name, ScalarType type, size_t count) {
  properties.push_back({std::move(name), type, stride, count});
  stride += ScalarSize(type) * count;
}

StatusOr<PointCloud> DecodeRecords(const RecordLayout& layout, size_t count, const std::string& path,
                                   uint64_t max_bytes, const RecordSource& source) {
  const FieldMap map(layout);
  if (!map.position) return InvalidArgument(path + ": the points need x, y and z");
  PointCloud cloud;
  cloud.fields = map.Fields();
  const uint64_t per_point = cloud.BytesPerPoint();
  if (count > max_bytes / per_point) {
    return ResourceExhausted(path + ": " + std::to_string(count) + " points of " + std::to_string(per_point) +
                             " bytes take more than the limit of " + std::to_string(max_bytes) + " bytes");
  }
  cloud.Resize(count);

  constexpr size_t kBlockPoints = 16384;
  std::vector<char> block(std::min(count, kBlockPoints) * layout.stride);
  for (size_t begin = 0; begin < count; begin += kBlockPoints) {
    const size_t points = std::min(kBlockPoints, count - begin);
    RETURN_IF_ERROR(source(block.data(), begin, points));
    for (size_t k = 0; k < points; ++k) map.Decode(block.data() + k * layout.stride, begin + k, cloud);
  }
  return cloud;
}

StatusOr<PointCloud> ReadRecords(std::istream& in, const RecordLayout& layout, size_t count,
                                 const std::string& path, uint64_t max_bytes) {
  return DecodeRecords(layout, count, path, max_bytes, [&](char* out, size_t first, size_t points) -> Status {
    if (!in.read(out, static_cast<std::streamsize>(points * layout.stride))) {
      return DataLoss(path + ": read failed at point " + std::to_string(first));
    }
    return Status::Ok();
  });
}

}  // namespace vscan::cloud_records
