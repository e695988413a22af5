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
  kFieldCleanPosition = 1u << 6,
  kFieldIncidence = 1u << 7,
  kFieldStatus = 1u << 8,
  kFieldEstimatedNormal = 1u << 9,
  kFieldsDefault = kFieldPosition | kFieldNormal | kFieldRange | kFieldIntensity | kFieldInstanceId,
  kFieldsAll = kFieldsDefault | kFieldPixel,
  // Per-point ground truth of the measurement model.
  kFieldsGroundTruth = kFieldCleanPosition | kFieldIncidence | kFieldStatus,
};

// What became of a point's ray; values match vscan.v1.PointStatus.
enum class PointStatus : uint8_t {
  kUnspecified = 0,
  kMeasured = 1,
  kOutlier = 2,
  kFlyingPixel = 3,
  kRejectedOutOfRange = 4,
  kRejectedShadowed = 5,
  kRejectedGrazing = 6,
  kRejectedDim = 7,
  kRejectedUnlit = 8,
  // The returned signal (docs/SENSORS.md): too weak to decode above its noise, or past the full well.
  kRejectedDark = 9,
  kRejectedSaturated = 10,
  // Structured light: the projector's direct light does not stand above the indirect light by the
  // returned light's interreflection_ratio, so the pattern does not decode.
  kRejectedInterreflection = 11,
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
  std::vector<Eigen::Vector3f> clean_positions;
  std::vector<float> incidence_angles;  // radians
  std::vector<uint8_t> statuses;        // PointStatus values
  std::vector<Eigen::Vector3f> estimated_normals;

  size_t size() const { return positions.size(); }
  bool Has(PointFields f) const { return (fields & f) != 0; }
  // Resizes every array the fields name, clears the others.
  void Resize(size_t n);
  // Bytes per point over the present fields.
  size_t BytesPerPoint() const;
};

static_assert(sizeof(Eigen::Vector3f) == 12, "positions must pack as 3 float32");

}  // namespace vscan
