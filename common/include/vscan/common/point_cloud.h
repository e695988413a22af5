#pragma once
// A point cloud as separate arrays (structure of arrays), the layout the wire format uses.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace vscan {

// Which per-point arrays a cloud carries (bit flags).
enum PointFields : uint32_t {
  kFieldPosition = 1u << 0,
  kFieldNormal = 1u << 1,
  kFieldRange = 1u << 2,
  kFieldIntensity = 1u << 3,
  kFieldInstanceId = 1u << 4,
  kFieldPixel = 1u << 5,
  kFieldsDefault = kFieldPosition | kFieldNormal | kFieldRange | kFieldIntensity | kFieldInstanceId,
  kFieldsAll = kFieldsDefault | kFieldPixel,
};

// Positions are always present; other arrays are empty or have size() elements.
struct PointCloud {
  uint32_t fields = kFieldPosition;
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;
  std::vector<float> ranges;
  std::vector<float> intensities;
  std::vector<uint32_t> instance_ids;
  std::vector<uint32_t> pixels;

  size_t size() const { return positions.size(); }
  bool Has(PointFields f) const { return (fields & f) != 0; }
  // Resizes every array the fields name, clears the others.
  void Resize(size_t n);
  // Bytes per point over the present fields.
  size_t BytesPerPoint() const;
};

static_assert(sizeof(Eigen::Vector3f) == 12, "positions must pack as 3 float32");

}  // namespace vscan
