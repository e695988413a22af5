#pragma once
// One colour per point, from a chosen field of the cloud.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"
#include "vscan/render/view.h"

namespace vscan::render {

enum class ColourMode {
  kDepth,      // distance from the eye, nearest point 0 to farthest 1 on Turbo
  kIntensity,  // grey, 0 black to the cloud's largest intensity white
  kInstance,   // InstanceColour(id)
  kNormal,     // (n + 1) / 2 as RGB
  kHeight,     // position along view.up, lowest point 0 to highest 1 on Turbo
  kStatus,     // StatusColour(status): measured grey, artefacts and each reject reason their own colour
};

// Measured light grey, outlier red, flying pixel orange, out of range purple, shadowed blue,
// grazing yellow, dim dark grey, unlit cyan; anything else black.
Eigen::Vector3f StatusColour(uint8_t status);

// depth, intensity, instance, normal, height or status; INVALID_ARGUMENT naming --color otherwise.
StatusOr<ColourMode> ParseColourMode(const std::string& name);
const char* ColourModeName(ColourMode mode);

// FAILED_PRECONDITION naming --color and the field when the cloud lacks the field the mode reads.
StatusOr<std::vector<Eigen::Vector3f>> CloudColours(const PointCloud& cloud, ColourMode mode, const View& view);

}  // namespace vscan::render
