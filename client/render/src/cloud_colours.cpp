#include "vscan/render/cloud_colours.h"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

#include "vscan/render/colour_map.h"

namespace vscan::render {
namespace {

constexpr std::array<std::pair<const char*, ColourMode>, 6> kModes = {{
    {"depth", ColourMode::kDepth},
    {"intensity", ColourMode::kIntensity},
    {"instance", ColourMode::kInstance},
    {"normal", ColourMode::kNormal},
    {"height", ColourMode::kHeight},
    {"status", ColourMode::kStatus},
}};

// Maps each value linearly from [min, max] of all values onto Turbo.
std::vector<Eigen::Vector3f> TurboOf(const std::vector<float>& values) {
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (const float v : values) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  const float scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
  std::vector<Eigen::Vector3f> out(values.size());
  for (size_t i = 0; i < values.size(); ++i) out[i] = Turbo((values[i] - lo) * scale);
  return out;
}

Status Missing(ColourMode mode, const char* field) {
  return FailedPrecondition(std::string("--color ") + ColourModeName(mode) + ": the cloud has no " + field +
                            " field (scan with --fields " + field + " or all)");
}

}  // namespace

Eigen::Vector3f StatusColour(uint8_t status) {
  switch (static_cast<PointStatus>(status)) {
    case PointStatus::kMeasured: return {0.8f, 0.8f, 0.8f};
    case PointStatus::kOutlier: return {0.9f, 0.1f, 0.1f};
    case PointStatus::kFlyingPixel: return {1.0f, 0.55f, 0.0f};
    case PointStatus::kRejectedOutOfRange: return {0.55f, 0.2f, 0.75f};
    case PointStatus::kRejectedShadowed: return {0.1f, 0.3f, 0.9f};
    case PointStatus::kRejectedGrazing: return {0.95f, 0.85f, 0.1f};
    case PointStatus::kRejectedDim: return {0.3f, 0.3f, 0.3f};
    case PointStatus::kRejectedUnlit: return {0.1f, 0.8f, 0.85f};
    case PointStatus::kRejectedDark: return {0.25f, 0.2f, 0.45f};
    case PointStatus::kRejectedInterreflection: return {0.9f, 0.5f, 0.8f};
    case PointStatus::kRejectedSaturated: return {1.0f, 1.0f, 0.6f};
    case PointStatus::kUnspecified: break;
  }
  return Eigen::Vector3f::Zero();
}

StatusOr<ColourMode> ParseColourMode(const std::string& name) {
  for (const auto& [text, mode] : kModes) {
    if (name == text) return mode;
  }
  return InvalidArgument("--color: unknown colour mode '" + name + "' (depth, intensity, instance, normal, height, status)");
}

const char* ColourModeName(ColourMode mode) {
  for (const auto& [text, m] : kModes) {
    if (m == mode) return text;
  }
  return "?";
}

StatusOr<std::vector<Eigen::Vector3f>> CloudColours(const PointCloud& cloud, ColourMode mode, const View& view) {
  const size_t n = cloud.size();
  std::vector<Eigen::Vector3f> out;
  switch (mode) {
    case ColourMode::kDepth:
    case ColourMode::kHeight: {
      const Eigen::Vector3f up = view.up.normalized();
      std::vector<float> values(n);
      for (size_t i = 0; i < n; ++i) {
        values[i] = mode == ColourMode::kDepth ? (cloud.positions[i] - view.eye).norm() : cloud.positions[i].dot(up);
      }
      return TurboOf(values);
    }
    case ColourMode::kIntensity: {
      if (!cloud.Has(kFieldIntensity)) return Missing(mode, "intensity");
      float hi = 0;
      for (const float v : cloud.intensities) hi = std::max(hi, v);
      const float scale = hi > 0 ? 1.0f / hi : 0.0f;
      out.resize(n);
      for (size_t i = 0; i < n; ++i) out[i].setConstant(std::clamp(cloud.intensities[i] * scale, 0.0f, 1.0f));
      return out;
    }
    case ColourMode::kInstance:
      if (!cloud.Has(kFieldInstanceId)) return Missing(mode, "instance");
      out.resize(n);
      for (size_t i = 0; i < n; ++i) out[i] = InstanceColour(cloud.instance_ids[i]);
      return out;
    case ColourMode::kNormal:
      if (!cloud.Has(kFieldNormal)) return Missing(mode, "normal");
      out.resize(n);
      for (size_t i = 0; i < n; ++i) {
        out[i] = ((cloud.normals[i] + Eigen::Vector3f::Ones()) / 2).cwiseMax(0.0f).cwiseMin(1.0f);
      }
      return out;
    case ColourMode::kStatus:
      if (!cloud.Has(kFieldStatus)) return Missing(mode, "status");
      out.resize(n);
      for (size_t i = 0; i < n; ++i) out[i] = StatusColour(cloud.statuses[i]);
      return out;
  }
  return Internal("--color: unhandled colour mode");
}

}  // namespace vscan::render
