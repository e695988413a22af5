#pragma once
// What binary PLY and PCD clouds have in common: one fixed-size record per point with scalar
// properties at fixed offsets. The format readers parse their headers into a RecordLayout; the
// records are then decoded here, once, so that every field reads back the same from either format.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <istream>
#include <string>
#include <vector>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::cloud_records {

enum class ScalarType : uint8_t {
  kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kInt64, kUint64, kFloat32, kFloat64
};

size_t ScalarSize(ScalarType type);

struct RecordProperty {
  std::string name;
  ScalarType type = ScalarType::kFloat32;
  size_t offset = 0;  // bytes from the start of the record
  size_t count = 1;   // values of `type` in a row (PCD COUNT)
};

struct RecordLayout {
  std::vector<RecordProperty> properties;
  size_t stride = 0;  // bytes per record

  // Appends a property of `count` values; only the first is read.
  void Add(std::string name, ScalarType type, size_t count = 1);
};

// Reads `count` records of `layout` from `in`, positioned at the first, into a cloud with every
// field the layout carries, each under vscan's PLY or PCD name (see cloud_io.h). INVALID_ARGUMENT
// naming `path` without x, y and z; RESOURCE_EXHAUSTED, before anything is allocated, when the
// cloud would take more than max_bytes (PointCloud::BytesPerPoint() per point); DATA_LOSS when the
// stream ends early.
StatusOr<PointCloud> ReadRecords(std::istream& in, const RecordLayout& layout, size_t count,
                                 const std::string& path, uint64_t max_bytes);

// Writes `points` records (points * layout.stride bytes) starting at record `first` into `out`;
// called with consecutive blocks, and only after the max_bytes check has passed.
using RecordSource = std::function<Status(char* out, size_t first, size_t points)>;
// As ReadRecords, with the records coming from `source` (ASCII text, decompressed data).
StatusOr<PointCloud> DecodeRecords(const RecordLayout& layout, size_t count, const std::string& path,
                                   uint64_t max_bytes, const RecordSource& source);

}  // namespace vscan::cloud_records
