#pragma once
// A picture of coverage: the ground-truth samples drawn from four sides (front, right, back, left
// about the up axis, one panel each), covered ones shaded grey by their depth, uncovered ones red.

#include <span>
#include <string>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::evaluation {

struct CoverageImageOptions {
  // Size of one panel in pixels; the image is 2 x 2 panels.
  int panel_size = 400;
  // The up axis of the object (the table's axis).
  Eigen::Vector3f up = Eigen::Vector3f::UnitZ();
};

// PNG bytes. covered has one entry per sample. InvalidArgument names "samples", "covered" or
// "coverage_image.panel_size".
StatusOr<std::string> RenderCoveragePng(std::span<const Eigen::Vector3f> samples, std::span<const uint8_t> covered,
                                        const CoverageImageOptions& options = {});

}  // namespace vscan::evaluation
