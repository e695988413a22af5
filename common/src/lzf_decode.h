#pragma once
// LZF decompression (the codec of PCD's binary_compressed data), bounded by both buffers.

#include <cstddef>
#include <string_view>

namespace vscan::cloud_records {

// The most an LZF stream expands: a 3-byte back-reference copies 264 bytes.
inline constexpr size_t kLzfMaxRatio = 88;

// Decompresses `in` into exactly out_size bytes at out; false when the stream is malformed (a
// reference before the start, a run past either end) or yields any other length.
bool LzfDecompress(std::string_view in, char* out, size_t out_size);

}  // namespace vscan::cloud_records
