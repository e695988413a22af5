#pragma once
// Reads binary PCD v0.7 clouds such as WritePcd produces (any field order, 1/2/4/8-byte scalars).

#include <string>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::render {

StatusOr<PointCloud> ReadPcd(const std::string& path);

}  // namespace vscan::render
