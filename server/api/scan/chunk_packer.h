#pragma once
// Packs a streamed scan's row blocks straight into chunk messages on the scanning thread and
// queues each full chunk for writing; the cast pauses while the outbox's window is full.

#include <cstddef>
#include <cstdint>
#include <memory>

#include "api/scan/scan_outbox.h"
#include "raycast/row_sink.h"

namespace vscan::api {

class ChunkPacker final : public raycast::RowSink {
 public:
  ChunkPacker(uint32_t fields, size_t points_per_chunk, ScanOutbox& outbox);

  void Accept(const raycast::RowBlock& block) override;
  bool HasRoom() override { return outbox_.HasRoom(); }
  void WaitForRoom() override { outbox_.WaitForRoom(); }
  // Queues the last, partly filled chunk.
  void Flush();

  uint64_t points() const { return points_; }
  uint32_t chunks() const { return chunks_; }

 private:
  // Copies points [begin, begin + n) of row r of the block into the open chunk.
  void CopyRow(const raycast::RowBlock& block, uint32_t r, uint32_t begin, uint32_t n);
  void Open();
  void Ship();

  const uint32_t fields_;
  const size_t points_per_chunk_;
  ScanOutbox& outbox_;
  std::unique_ptr<v1::ScanResponse> open_;
  size_t in_open_ = 0;
  uint64_t points_ = 0;
  uint32_t chunks_ = 0;
};

}  // namespace vscan::api
