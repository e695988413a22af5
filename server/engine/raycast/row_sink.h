#pragma once
// Where a streaming scan delivers its points: blocks of whole image rows, in row order, while
// later rows are still being cast.

#include <array>
#include <cstdint>

namespace vscan::raycast {

// The points of up to four consecutive image rows. Row r's points take slots
// [r * stride, r * stride + count[r]) of each array (positions and normals: three floats a slot);
// arrays of fields the scan was not asked for hold nothing meaningful.
struct RowBlock {
  uint32_t first_row = 0;
  uint32_t rows = 0;
  uint32_t stride = 0;
  std::array<uint32_t, 4> count{};
  const float* positions = nullptr;
  const float* normals = nullptr;
  const float* ranges = nullptr;
  const float* intensities = nullptr;
  const uint32_t* instance_ids = nullptr;
  const uint32_t* pixels = nullptr;

  uint32_t total() const { return count[0] + count[1] + count[2] + count[3]; }
};

class RowSink {
 public:
  virtual ~RowSink() = default;
  // One block, in row order, one call at a time on one of the scan's threads; the arrays are
  // reused once it returns.
  virtual void Accept(const RowBlock& block) = 0;
  // Polled before each strip is started: false pauses the cast (strips already started still
  // arrive) until WaitForRoom returns.
  virtual bool HasRoom() = 0;
  // Blocks the thread that called the scan (never a pool thread) until there is room again or the
  // scan's cancel flag is set.
  virtual void WaitForRoom() = 0;
};

}  // namespace vscan::raycast
