#pragma once
// Traces one strip of four image rows in 4x4 packets and computes the fields of its hits.

#include <array>
#include <cstdint>
#include <memory>

#include "raycast/row_sink.h"
#include "raycast/scan_setup.h"

namespace vscan::raycast {

// The points of one strip, laid out like PointCloud's arrays, row by row: row r's points take
// slots [r * stride, r * stride + count[r]); positions and normals take three floats a slot.
class StripHits {
 public:
  // Rows of row_stride slots (the width padded to whole packets).
  explicit StripHits(uint32_t row_stride);

  float* positions = nullptr;
  float* normals = nullptr;
  float* ranges = nullptr;
  float* intensities = nullptr;
  uint32_t* instance_ids = nullptr;
  uint32_t* pixels = nullptr;
  std::array<uint32_t, kPacketSide> count{};
  uint32_t stride = 0;
  // The image rows this strip holds.
  uint32_t first_row = 0;
  uint32_t rows = 0;
  float min_range = 0;
  float max_range = 0;

  uint32_t total() const { return count[0] + count[1] + count[2] + count[3]; }
  RowBlock Block() const;

 private:
  struct Free {
    void operator()(void* p) const;
  };
  std::unique_ptr<void, Free> block_;
};

// Casts the rays of image rows [4 * strip, 4 * strip + 4) and fills hits.
void TraceStrip(const ScanSetup& setup, uint32_t strip, StripHits& hits);

}  // namespace vscan::raycast
