#pragma once
// A scan's points as Scan stream messages: the header first, chunks packed on the scanning thread
// (rows as they are cast, or the finished cloud a window at a time), the statistics last.

#include <atomic>
#include <optional>

#include "api/scan/chunk_packer.h"
#include "api/scan/scan_outbox.h"
#include "service/scan/scan_run.h"

namespace vscan::api {

class ScanWriter final : public service::ScanConsumer {
 public:
  ScanWriter(const service::ScanPlan& plan, size_t points_per_chunk, ScanOutbox& outbox,
             const std::atomic<bool>& cancel);

  void Begin(uint64_t scene_revision, std::optional<uint64_t> points) override;
  void Accept(const raycast::RowBlock& block) override { packer_.Accept(block); }
  bool HasRoom() override { return outbox_.HasRoom(); }
  void WaitForRoom() override { outbox_.WaitForRoom(); }
  Status Cloud(const PointCloud& cloud) override;

  // The per-pixel images in bands of rows of about a chunk's size, after the cloud.
  Status Images(const capture::PixelImages& images);

  // The last message: the scan's figures, what was sent and the server's time for the call.
  void Finish(const service::ScanOutcome& outcome, double total_ms);

 private:
  const service::ScanPlan& plan_;
  ScanOutbox& outbox_;
  const std::atomic<bool>& cancel_;
  const size_t points_per_chunk_;
  ChunkPacker packer_;
  uint64_t cloud_points_ = 0;
  uint32_t cloud_chunks_ = 0;
};

}  // namespace vscan::api
