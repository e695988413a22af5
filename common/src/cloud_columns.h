#pragma once
// The record layout of the binary PLY and PCD files: one column per scalar, interleaved per point.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::cloud_file {

// One scalar column of the interleaved record (4-byte float/uint or 1-byte uchar), with its names
// in each format.
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

}  // namespace vscan::cloud_file
