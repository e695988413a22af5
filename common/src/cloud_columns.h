#pragma once
// The record layout of the binary PLY and PCD files: one column per scalar, interleaved per point.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::cloud_file {

// One scalar column of the interleaved record (4-byte float or int, or 1-byte uchar), with its
// names in each format. Integers are int32 rather than uint32: Open3D's PLY reader drops uint32
// properties, and PCL reads both.
struct Column {
  const char* ply_name;
  const char* pcd_name;
  bool is_float;
  const char* base;  // first value of this column; stride between points is `step` bytes
  size_t step;
  size_t size = 4;
};

// The columns of cloud's fields, pointing into its arrays.
std::vector<Column> Columns(const PointCloud& cloud);
size_t RecordBytes(const std::vector<Column>& cols);
// Every present array has size() values.
Status CheckConsistent(const PointCloud& cloud);

// The headers for `points` points. With pad set, the header carries a padding comment of that
// many extra spaces, so that a header written before the count was known can be rewritten in place.
std::string PlyHeader(const std::vector<Column>& cols, uint64_t points, std::optional<size_t> pad);
std::string PcdHeader(const std::vector<Column>& cols, uint64_t points, std::optional<size_t> pad);

// An organised PCD's WIDTH x HEIGHT and VIEWPOINT (tx ty tz qw qx qy qz), the points given row by row.
struct PcdImage {
  uint32_t width = 0, height = 0;
  double viewpoint[7] = {0, 0, 0, 1, 0, 0, 0};
};
std::string PcdHeader(const std::vector<Column>& cols, const PcdImage& image);

}  // namespace vscan::cloud_file
