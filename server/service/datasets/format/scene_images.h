#pragma once
// The images of one scene as the files hold them: depth in units of the depth scale, the index of
// the ground-truth object seen at each pixel, and what each object's visible pixels add up to.

#include <cstdint>
#include <vector>

#include "service/datasets/format/dataset_frame.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// Depth as round(depth_mm / depth_scale_mm), 0 where nothing was measured. OutOfRange names the
// first pixel whose depth does not fit 16 bits (or is negative).
StatusOr<std::vector<uint16_t>> QuantizeDepth(const DatasetFrame& frame, double depth_scale_mm);

// Per pixel: 1 + the index of the ground-truth object whose instance is seen there, else 0 (the
// background and anything that is not a ground-truth part, such as the bin).
std::vector<uint16_t> ObjectIndexImage(const DatasetFrame& frame);

struct VisibleStats {
  ImageBox box;             // the box around the object's pixels; x = y = -1, size 0 when none
  uint64_t pixels = 0;      // pixels showing the object
  uint64_t with_depth = 0;  // of those, pixels with a depth measurement
};

// One entry per ground-truth object, from the object index image and the quantized depth.
std::vector<VisibleStats> VisibleStatsOf(const std::vector<uint16_t>& object_index, const std::vector<uint16_t>& depth,
                                         uint32_t width, size_t object_count);

// 255 where the object with this index is seen, else 0.
std::vector<uint8_t> VisibleMask(const std::vector<uint16_t>& object_index, size_t object);
// 255 at the object's alone_mask pixels (its silhouette, occlusion ignored), else 0.
std::vector<uint8_t> AloneMask(const GroundTruthObject& object, size_t pixels);

// The frame's sizes agree, the intrinsics are positive and finite, objects are 1-based part types
// with distinct instance ids (at most 65535 of them), and each object's visible_pixels equals its
// count in the instance image.
Status CheckFrame(const DatasetFrame& frame);

}  // namespace vscan::service::dataset
