#pragma once
// Point cloud files: binary PLY and PCD, written and read back with every field vscan writes.

#include <cstdint>
#include <string>
#include <string_view>

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
// The bytes WritePly writes, in memory.
StatusOr<std::string> EncodePly(const PointCloud& cloud);

// The readers take back every field the writers write (positions, normals, range, intensity,
// instance, pixel, and the ground truth: clean position, incidence, status, estimated normal),
// each under its PLY or its PCD name, in any order and any scalar type; fields they do not know
// are skipped. NOT_FOUND when the file cannot be opened, INVALID_ARGUMENT when it is malformed or
// lacks x, y or z, DATA_LOSS when it is truncated.

// Binary little-endian PLY: the vertex element; fixed-size elements before it and any after it
// (faces) are skipped.
StatusOr<PointCloud> ReadPly(const std::string& path);
// Binary PCD v0.7 (DATA binary; 1/2/4/8-byte F, U and I fields; the first value of a COUNT > 1
// field). WIDTH and HEIGHT are ignored: the cloud is POINTS long.
StatusOr<PointCloud> ReadPcd(const std::string& path);
// Picks the reader from the extension (.ply or .pcd).
StatusOr<PointCloud> ReadCloud(const std::string& path);

// The same readers over bytes in memory (uploads): `where` stands for the path in messages, a
// truncated file is DATA_LOSS as above, and a cloud whose arrays would take more than max_bytes
// (PointCloud::BytesPerPoint() per point) is RESOURCE_EXHAUSTED before anything is allocated.
StatusOr<PointCloud> ParsePly(std::string_view bytes, const std::string& where, uint64_t max_bytes);
StatusOr<PointCloud> ParsePcd(std::string_view bytes, const std::string& where, uint64_t max_bytes);

}  // namespace vscan
