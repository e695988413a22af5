#pragma once
// Point clouds for round-trip tests: every field filled with values that differ per point.

#include <cstddef>
#include <cstdint>

#include "vscan/common/point_cloud.h"

namespace vscan::test {

// n points carrying `fields`, with non-trivial values (fractions, high id bits, every status).
PointCloud MakeCloud(uint32_t fields, size_t n);

// Fails the calling test unless a and b carry the same fields with bit-identical values.
void ExpectSameCloud(const PointCloud& a, const PointCloud& b);

}  // namespace vscan::test
