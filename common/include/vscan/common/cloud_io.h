#pragma once
// Point cloud files: binary PLY and PCD written with every field vscan has, in types Open3D and PCL
// both read (float32; instance and pixel int32, since Open3D drops uint32 PLY properties; status
// uint8); read back from binary, ASCII and (PCD) binary_compressed files. Organised PCD (a scan as
// its range image): organized_pcd.h.

#include <cstdint>
#include <string>
#include <string_view>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan {

// Binary little-endian PLY: x y z [nx ny nz] [range] [intensity] [instance (int)] [pixel (int)]
// [clean_x clean_y clean_z] [incidence] [status (uchar)] [enx eny enz].
Status WritePly(const PointCloud& cloud, const std::string& path);
// Binary PCD v0.7 with the same fields (normal_x.., range, intensity, instance and pixel (4-byte I),
// clean_x.., incidence, status (1-byte U), est_normal_x..).
Status WritePcd(const PointCloud& cloud, const std::string& path);
// Picks the writer from the extension (.ply or .pcd).
Status WriteCloud(const PointCloud& cloud, const std::string& path);
// The bytes WritePly writes, in memory.
StatusOr<std::string> EncodePly(const PointCloud& cloud);

// The readers take back every field the writers write (positions, normals, range, intensity,
// instance, pixel, and the ground truth: clean position, incidence, status, estimated normal),
// each under its PLY or its PCD name, in any order and any scalar type (an int32 instance or pixel
// is taken as the bits of the uint32); fields they do not know are skipped. NOT_FOUND when the file
// cannot be opened, INVALID_ARGUMENT when it is malformed or lacks x, y or z, DATA_LOSS when it is
// truncated (a count the bytes cannot hold is caught before anything is allocated).

// PLY, binary little-endian or ASCII: the vertex element; fixed-size elements before it and any
// after it (faces, PCL's camera) are skipped.
StatusOr<PointCloud> ReadPly(const std::string& path);
// PCD v0.7, DATA binary, ascii or binary_compressed (LZF; both sizes checked against POINTS and the
// file before decompressing); 1/2/4/8-byte F, U and I fields; the first value of a COUNT > 1
// field. WIDTH and HEIGHT are ignored: the cloud is POINTS long, holes (NaN) included.
StatusOr<PointCloud> ReadPcd(const std::string& path);
// Picks the reader from the extension (.ply or .pcd).
StatusOr<PointCloud> ReadCloud(const std::string& path);

// The same readers over bytes in memory (uploads): `where` stands for the path in messages, a
// truncated file is DATA_LOSS as above, and a cloud whose arrays would take more than max_bytes
// (PointCloud::BytesPerPoint() per point) is RESOURCE_EXHAUSTED before anything is allocated.
StatusOr<PointCloud> ParsePly(std::string_view bytes, const std::string& where, uint64_t max_bytes);
StatusOr<PointCloud> ParsePcd(std::string_view bytes, const std::string& where, uint64_t max_bytes);

}  // namespace vscan
