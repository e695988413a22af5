#pragma once
// Point cloud and mesh files: binary PLY and PCD writers, a PLY reader for round trips.

#include <string>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan {

// Binary little-endian PLY: x y z [nx ny nz] [range] [intensity] [instance] [pixel]
// [clean_x clean_y clean_z] [incidence] [status (uchar)] [enx eny enz].
Status WritePly(const PointCloud& cloud, const std::string& path);
// Binary PCD v0.7 with the same fields (normal_x.., range, intensity, instance, pixel, clean_x..,
// incidence, status (1-byte U), est_normal_x..).
Status WritePcd(const PointCloud& cloud, const std::string& path);
// Picks the writer from the extension (.ply or .pcd).
Status WriteCloud(const PointCloud& cloud, const std::string& path);
// Reads a binary little-endian PLY written by WritePly (vertex element only).
StatusOr<PointCloud> ReadPly(const std::string& path);

}  // namespace vscan
