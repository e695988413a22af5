#pragma once
// Grows the cloud strip by strip, in row order.

#include <cstddef>

#include "raycast/row_sink.h"
#include "vscan/common/point_cloud.h"

namespace vscan::raycast {

// Room for n points in every array the cloud's fields name, so appending never reallocates;
// pages never written cost nothing.
void ReserveForEveryPixel(PointCloud& cloud, size_t n);

// Appends the block's points (the cloud must have room for them).
void AppendRows(const RowBlock& block, PointCloud& cloud);

// Gives back the reserved room when most of it went unused.
void TrimExcess(PointCloud& cloud);

}  // namespace vscan::raycast
