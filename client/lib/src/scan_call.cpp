#include <algorithm>
#include <cstring>

#include "huge_pages.h"
#include "vscan/client/client.h"
#include "vscan/common/grpc_status.h"
#include "vscan/common/point_chunks.h"
#include "vscan/common/proto_convert.h"

namespace vscan::client {
namespace {

// Upper bound on points reserved up front, so a bogus header cannot exhaust memory by itself.
constexpr uint64_t kMaxReservedPoints = uint64_t{1} << 26;

template <typename T>
void Reserve(bool present, size_t n, std::vector<T>* array) {
  if (!present) return;
  array->reserve(n);
  AdviseHugePages(*array);
}

void Reserve(PointCloud* cloud, size_t n) {
  Reserve(true, n, &cloud->positions);
  Reserve(cloud->Has(kFieldNormal), n, &cloud->normals);
  Reserve(cloud->Has(kFieldRange), n, &cloud->ranges);
  Reserve(cloud->Has(kFieldIntensity), n, &cloud->intensities);
  Reserve(cloud->Has(kFieldInstanceId), n, &cloud->instance_ids);
  Reserve(cloud->Has(kFieldPixel), n, &cloud->pixels);
  Reserve(cloud->Has(kFieldCleanPosition), n, &cloud->clean_positions);
  Reserve(cloud->Has(kFieldIncidence), n, &cloud->incidence_angles);
  Reserve(cloud->Has(kFieldStatus), n, &cloud->statuses);
  Reserve(cloud->Has(kFieldEstimatedNormal), n, &cloud->estimated_normals);
}

// Folds the stream's messages into a ScanResult, checking their order and sizes.
class ScanAssembler {
 public:
  explicit ScanAssembler(const ScanCallbacks& callbacks) : callbacks_(callbacks) {}

  Status Add(const v1::ScanResponse& message) {
    switch (message.part_case()) {
      case v1::ScanResponse::kHeader: return OnHeader(message.header());
      case v1::ScanResponse::kChunk: return OnChunk(message.chunk());
      case v1::ScanResponse::kStatistics:
        if (!have_header_) return DataLoss("scan stream: statistics before the header");
        if (have_stats_) return DataLoss("scan stream: second statistics");
        result_.stats = message.statistics();
        have_stats_ = true;
        return Status::Ok();
      case v1::ScanResponse::kPixelRows: return OnPixelRows(message.pixel_rows());
      case v1::ScanResponse::PART_NOT_SET: break;
    }
    return Status::Ok();
  }

  StatusOr<ScanResult> Finish() && {
    if (!have_header_) return DataLoss("scan stream: ended without a header");
    if (!have_stats_) return DataLoss("scan stream: ended without statistics");
    // A streamed scan's header announces no count (0); its statistics carry the total.
    const uint64_t expected = result_.header.points() != 0 ? result_.header.points() : result_.stats.streamed_points();
    if (received_ != expected) {
      return DataLoss("scan stream: received " + std::to_string(received_) + " of " +
                      std::to_string(expected) + " points");
    }
    if (result_.images && rows_received_ != result_.images->height) {
      return DataLoss("scan stream: received " + std::to_string(rows_received_) + " of " +
                      std::to_string(result_.images->height) + " rows of pixel images");
    }
    return std::move(result_);
  }

 private:
  Status OnHeader(const v1::ScanHeader& header) {
    if (have_header_) return DataLoss("scan stream: second header");
    ASSIGN_OR_RETURN(const uint32_t fields, FieldsFromProto(header.fields(), "header.fields"));
    result_.header = header;
    result_.cloud.fields = fields;
    // Room for a point per ray when the count is not announced: chunks land in the final arrays,
    // and pages no point reaches are never touched.
    const uint64_t room = header.points() != 0 ? header.points() : header.rays();
    if (!callbacks_.on_chunk) Reserve(&result_.cloud, static_cast<size_t>(std::min(room, kMaxReservedPoints)));
    have_header_ = true;
    if (header.pixel_images()) {
      if (uint64_t{header.width()} * header.height() > kMaxReservedPoints) {
        return DataLoss("scan stream: pixel images of " + std::to_string(header.width()) + " x " +
                        std::to_string(header.height()) + " pixels");
      }
      PixelImages& images = result_.images.emplace();
      images.width = header.width();
      images.height = header.height();
      images.reasons.assign(size_t{images.width} * images.height, 0);
      images.gray.assign(images.reasons.size(), 0);
    }
    if (callbacks_.on_header) callbacks_.on_header(result_.header);
    return Status::Ok();
  }

  Status OnChunk(const v1::PointChunk& chunk) {
    if (!have_header_) return DataLoss("scan stream: chunk before the header");
    if (result_.header.points() != 0 && received_ + chunk.count() > result_.header.points()) {
      return DataLoss("scan stream: more points than the header announced (" +
                      std::to_string(result_.header.points()) + ")");
    }
    if (callbacks_.on_chunk) {
      RETURN_IF_ERROR(CheckChunk(chunk, result_.cloud.fields));
      RETURN_IF_ERROR(callbacks_.on_chunk(chunk));
    } else {
      RETURN_IF_ERROR(AppendChunk(chunk, &result_.cloud));
    }
    received_ += chunk.count();
    if (callbacks_.on_progress) callbacks_.on_progress(received_, result_.header.points());
    return Status::Ok();
  }

  // Bands arrive in order after the last chunk and before the statistics.
  Status OnPixelRows(const v1::PixelRows& rows) {
    if (!result_.images) return DataLoss("scan stream: pixel rows the header did not announce");
    if (have_stats_) return DataLoss("scan stream: pixel rows after the statistics");
    PixelImages& images = *result_.images;
    if (rows.first_row() != rows_received_ || rows.row_count() == 0 ||
        rows.row_count() > images.height - rows_received_) {
      return DataLoss("scan stream: pixel rows " + std::to_string(rows.first_row()) + " + " +
                      std::to_string(rows.row_count()) + " after " + std::to_string(rows_received_) + " of " +
                      std::to_string(images.height));
    }
    const size_t begin = size_t{rows.first_row()} * images.width, count = size_t{rows.row_count()} * images.width;
    if (rows.reasons().size() != count || rows.gray().size() != count * sizeof(uint16_t)) {
      return DataLoss("scan stream: pixel rows of the wrong size");
    }
    std::memcpy(images.reasons.data() + begin, rows.reasons().data(), count);
    const auto* gray = reinterpret_cast<const unsigned char*>(rows.gray().data());
    for (size_t i = 0; i < count; ++i) {
      images.gray[begin + i] = static_cast<uint16_t>(gray[2 * i] | (gray[2 * i + 1] << 8));
    }
    rows_received_ += rows.row_count();
    return Status::Ok();
  }

  const ScanCallbacks& callbacks_;
  ScanResult result_;
  uint32_t rows_received_ = 0;
  uint64_t received_ = 0;
  bool have_header_ = false;
  bool have_stats_ = false;
};

}  // namespace

StatusOr<ScanResult> Client::Scan(const v1::ScanRequest& request, const ScanCallbacks& callbacks) {
  grpc::ClientContext context;
  PrepareContext(&context, options_.stream_timeout);
  auto reader = scans_->Scan(&context, request);
  ScanAssembler assembler(callbacks);
  Status local;
  v1::ScanResponse message;
  while (reader->Read(&message)) {
    local = assembler.Add(message);
    if (!local.ok()) {
      context.TryCancel();
      while (reader->Read(&message)) {
      }
      break;
    }
  }
  const grpc::Status status = reader->Finish();
  if (!local.ok()) return local;
  if (!status.ok()) return FromGrpc(status);
  return std::move(assembler).Finish();
}

}  // namespace vscan::client
