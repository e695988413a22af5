#include "api/scan/scan_writer.h"

#include <algorithm>
#include <memory>

#include "api/scan/scan_messages.h"
#include "geometry/little_endian.h"
#include "observability/server_metrics.h"
#include "vscan/common/point_chunks.h"

namespace vscan::api {

ScanWriter::ScanWriter(const service::ScanPlan& plan, size_t points_per_chunk, ScanOutbox& outbox,
                       const std::atomic<bool>& cancel)
    : plan_(plan), outbox_(outbox), cancel_(cancel), points_per_chunk_(points_per_chunk),
      packer_(plan.fields, points_per_chunk, outbox) {}

void ScanWriter::Begin(uint64_t scene_revision, std::optional<uint64_t> points) {
  auto message = std::make_unique<v1::ScanResponse>();
  v1::ScanHeader* header = message->mutable_header();
  FillScanHeader(plan_, scene_revision, header);
  if (points) {
    const size_t per_chunk = points_per_chunk_;
    header->set_points(*points);
    header->set_chunk_count(static_cast<uint32_t>((*points + per_chunk - 1) / per_chunk));
  }
  outbox_.Push(std::move(message));
}

Status ScanWriter::Cloud(const PointCloud& cloud) {
  const size_t per_chunk = points_per_chunk_;
  const auto chunks = static_cast<uint32_t>((cloud.size() + per_chunk - 1) / per_chunk);
  for (uint32_t i = 0; i < chunks; ++i) {
    if (!outbox_.HasRoom()) outbox_.WaitForRoom();
    if (cancel_.load()) return Cancelled("scan cancelled");
    const size_t begin = size_t{i} * per_chunk;
    auto message = std::make_unique<v1::ScanResponse>();
    PackChunk(cloud, begin, std::min(per_chunk, cloud.size() - begin), i, message->mutable_chunk());
    outbox_.Push(std::move(message));
  }
  cloud_points_ = cloud.size();
  cloud_chunks_ = chunks;
  return Status::Ok();
}

Status ScanWriter::Images(const capture::PixelImages& images) {
  const size_t row_bytes = size_t{images.width} * (sizeof(uint8_t) + sizeof(uint16_t));
  const uint32_t band = static_cast<uint32_t>(std::max<size_t>(1, plan_.chunk_bytes / std::max<size_t>(1, row_bytes)));
  for (uint32_t first = 0; first < images.height; first += band) {
    if (!outbox_.HasRoom()) outbox_.WaitForRoom();
    if (cancel_.load()) return Cancelled("scan cancelled");
    const uint32_t rows = std::min(band, images.height - first);
    const size_t begin = size_t{first} * images.width, count = size_t{rows} * images.width;
    auto message = std::make_unique<v1::ScanResponse>();
    v1::PixelRows* out = message->mutable_pixel_rows();
    out->set_first_row(first);
    out->set_row_count(rows);
    out->set_reasons(images.reasons.data() + begin, count);
    std::string* gray = out->mutable_gray();
    gray->resize(count * sizeof(uint16_t));
    for (size_t i = 0; i < count; ++i) {
      geometry::StoreLe(gray->data() + i * sizeof(uint16_t), images.gray[begin + i], sizeof(uint16_t));
    }
    outbox_.Push(std::move(message));
  }
  return Status::Ok();
}

void ScanWriter::Finish(const service::ScanOutcome& outcome, double total_ms) {
  uint64_t points = cloud_points_;
  uint32_t chunks = cloud_chunks_;
  if (outcome.streamed) {
    packer_.Flush();
    points = packer_.points();
    chunks = packer_.chunks();
  }
  auto message = std::make_unique<v1::ScanResponse>();
  v1::ScanStatistics* s = message->mutable_statistics();
  FillScanStatistics(outcome.stats, outcome.measure, s);
  s->set_streamed_points(points);
  observability::Metrics().scan_points_sent.Increment(static_cast<double>(points));
  s->set_chunk_count(chunks);
  s->set_total_ms(total_ms);
  for (const service::ObjectTruth& object : outcome.objects) ObjectTruthToProto(object, s->add_objects());
  outbox_.Push(std::move(message));
}

}  // namespace vscan::api
