#include "scan/scan_to_file.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <optional>

#include "session/args.h"
#include "session/progress.h"
#include "vscan/common/cloud_file_writer.h"
#include "vscan/common/organized_pcd.h"
#include "vscan/common/point_chunks.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {

int CheckOutput(Context& ctx, const std::string& output, bool organized) {
  std::string ext = std::filesystem::path(output).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".ply" && ext != ".pcd") return ctx.UsageError("-o: output must end in .ply or .pcd");
  if (organized && ext != ".pcd") return ctx.UsageError("-o: --organized writes a PCD; output must end in .pcd");
  std::filesystem::path dir = std::filesystem::path(output).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    return ctx.LocalError(NotFound(output + ": directory " + dir.string() + " does not exist"));
  }
  return kExitOk;
}

namespace {

// The request with the pixel field added (to the default fields when none were asked).
v1::ScanRequest WithPixels(v1::ScanRequest request) {
  if (request.fields().empty()) FieldsToProto(kFieldsDefault, request.mutable_fields());
  const auto& fields = request.fields();
  if (std::find(fields.begin(), fields.end(), v1::POINT_FIELD_PIXEL) == fields.end()) {
    request.add_fields(v1::POINT_FIELD_PIXEL);
  }
  return request;
}

// Runs the scan behind a progress bar, timing its first chunk and its whole into out.
StatusOr<client::ScanResult> TimedScan(Context& ctx, client::Client& client, const v1::ScanRequest& request,
                                       client::ScanCallbacks callbacks, ScannedFile* out) {
  const auto start = std::chrono::steady_clock::now();
  const auto ms_since_start = [&start] {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  ProgressBar bar("scan", "points", !ctx.quiet() && !ctx.json());
  auto on_chunk = std::move(callbacks.on_chunk);
  callbacks.on_chunk = [&](const v1::PointChunk& chunk) -> Status {
    if (out->first_chunk_ms < 0) out->first_chunk_ms = ms_since_start();
    return on_chunk(chunk);
  };
  callbacks.on_progress = [&bar](uint64_t done, uint64_t total) { bar.Update(done, total); };
  auto result = client.Scan(request, callbacks);
  out->total_ms = ms_since_start();
  bar.Finish();
  return result;
}

// Scans into memory and writes the organised PCD once the scan has ended well.
int ScanToOrganizedPcd(Context& ctx, const v1::ScanRequest& request, const std::string& output, ScannedFile* out) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  PointCloud cloud;
  client::ScanCallbacks callbacks;
  callbacks.on_header = [&](const v1::ScanHeader& header) {
    const auto fields = FieldsFromProto(header.fields(), "header.fields");
    cloud.fields = fields.ok() ? *fields : kFieldPosition;
  };
  callbacks.on_chunk = [&](const v1::PointChunk& chunk) { return AppendChunk(chunk, &cloud); };
  auto result = TimedScan(ctx, *client, WithPixels(request), std::move(callbacks), out);
  if (!result.ok()) return ctx.ServerError(result.status());
  const v1::ScanHeader& header = result->header;
  RangeImageLayout image;
  image.width = header.width();
  image.height = header.height();
  // Sensor-frame points were seen from the origin; world-frame ones from the sensor's pose.
  if (header.frame() != v1::FRAME_SENSOR) {
    const auto pose = PoseFromProto(header.sensor_pose(), "header.sensor_pose");
    if (!pose.ok()) return ctx.LocalError(pose.status());
    image.viewpoint = *pose;
  }
  if (const Status written = WriteOrganizedPcd(cloud, image, output); !written.ok()) return ctx.LocalError(written);
  out->points = cloud.size();
  out->result = std::move(result).value();
  return kExitOk;
}

}  // namespace

int ScanToFile(Context& ctx, const v1::ScanRequest& request, const std::string& output, ScannedFile* out,
               bool organized) {
  if (organized) return ScanToOrganizedPcd(ctx, request, output, out);
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  // Chunks go to the file as they arrive (no cloud held in memory); it is renamed into place once
  // the scan has ended well. The client has checked the header's fields before on_header.
  std::optional<CloudFileWriter> writer;
  Status local_io;
  PointCloud block;
  client::ScanCallbacks callbacks;
  callbacks.on_header = [&](const v1::ScanHeader& header) {
    const auto fields = FieldsFromProto(header.fields(), "header.fields");
    block.fields = fields.ok() ? *fields : kFieldPosition;
    auto file = CloudFileWriter::Open(output, *CloudFileFormatOf(output), block.fields);
    if (file.ok()) {
      writer.emplace(std::move(file).value());
    } else {
      local_io = file.status();
    }
  };
  callbacks.on_chunk = [&](const v1::PointChunk& chunk) -> Status {
    if (!writer) return local_io;
    block.Resize(0);
    RETURN_IF_ERROR(AppendChunk(chunk, &block));
    local_io = writer->Append(block);
    return local_io;
  };
  auto result = TimedScan(ctx, *client, request, std::move(callbacks), out);
  if (!local_io.ok()) return ctx.LocalError(local_io);
  if (!result.ok()) return ctx.ServerError(result.status());
  if (!writer) return ctx.LocalError(Internal("scan: ended without a header"));

  const Status written = writer->Finish();
  if (!written.ok()) return ctx.LocalError(written);
  out->points = writer->points();
  out->result = std::move(result).value();
  return kExitOk;
}

}  // namespace vscan::cli
