#pragma once
// Packing a PointCloud into PointChunk messages (little-endian float32/uint32 arrays) and back.

#include <cstddef>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"
#include "vscan/v1/scan.pb.h"

namespace vscan {

// Points per chunk so that one chunk is about chunk_bytes.
size_t PointsPerChunk(uint32_t fields, size_t chunk_bytes);

// Copies points [begin, begin + count) of cloud into out.
void PackChunk(const PointCloud& cloud, size_t begin, size_t count, uint32_t index, v1::PointChunk* out);

// Appends a chunk to cloud, whose fields must already be set; checks every array's length.
Status AppendChunk(const v1::PointChunk& chunk, PointCloud* cloud);

// Checks that every array of chunk that fields name holds chunk.count() values.
Status CheckChunk(const v1::PointChunk& chunk, uint32_t fields);

}  // namespace vscan
