#include "service/clouds/cloud_import.h"

#include <cmath>
#include <string>
#include <vector>

#include "vscan/common/cloud_io.h"
#include "vscan/common/physical_limits.h"

namespace vscan::service {
namespace {

const std::string kWhere(kCloudDataField);

bool StartsWithLine(std::string_view bytes, std::string_view word) {
  if (!bytes.starts_with(word)) return false;
  const std::string_view rest = bytes.substr(word.size());
  return rest.starts_with('\n') || rest.starts_with("\r\n");
}

// The readers say "cloud data: <text>"; the status names the field apart, and a truncated file is
// the client's mistake here, not lost data.
Status AsUploadError(const Status& status) {
  const std::string_view lead = std::string_view(status.message()).substr(0, kWhere.size() + 2);
  const std::string text = lead == kWhere + ": " ? status.message().substr(lead.size()) : status.message();
  switch (status.code()) {
    case StatusCode::kResourceExhausted:
      return ResourceExhausted(kWhere, text + " (the smaller of --max-upload-mib and --max-request-memory-mib)");
    case StatusCode::kDataLoss:
    case StatusCode::kInvalidArgument: return InvalidArgument(kWhere, text);
    default: return status;
  }
}

// The first point whose coordinates are not finite or lie beyond the physical bound, named by its
// index and the file's names for the coordinates.
Status CheckPositions(const std::vector<Eigen::Vector3f>& points, std::string_view names) {
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    const bool finite = std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
    if (finite && p.cwiseAbs().maxCoeff() <= kMaxCoordinateM) continue;
    const std::string where = "points[" + std::to_string(i) + "] (" + std::string(names) + "): ";
    return InvalidArgument(kWhere,
                           where + (finite ? "beyond 10 km (|x|, |y|, |z| <= 1e4 m)" : "NaN or infinite value"));
  }
  return Status::Ok();
}

bool IsHole(const Eigen::Vector3f& p) { return std::isnan(p.x()) && std::isnan(p.y()) && std::isnan(p.z()); }

// Drops the points whose x, y and z are all NaN: the holes of an organised cloud (a range image
// written by vscan scan --organized, PCL or Open3D), which carry no measurement.
void DropHoles(PointCloud& cloud) {
  size_t kept = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (IsHole(cloud.positions[i])) continue;
    const auto move = [&](auto& v) {
      if (!v.empty()) v[kept] = v[i];
    };
    move(cloud.positions);
    move(cloud.normals);
    move(cloud.ranges);
    move(cloud.intensities);
    move(cloud.instance_ids);
    move(cloud.pixels);
    move(cloud.clean_positions);
    move(cloud.incidence_angles);
    move(cloud.statuses);
    move(cloud.estimated_normals);
    ++kept;
  }
  cloud.Resize(kept);
}

}  // namespace

std::optional<CloudFileFormat> DetectCloudFormat(std::string_view bytes) {
  if (StartsWithLine(bytes, "ply")) return CloudFileFormat::kPly;
  if (bytes.starts_with("# .PCD") || bytes.starts_with("VERSION") || bytes.starts_with("FIELDS")) {
    return CloudFileFormat::kPcd;
  }
  return std::nullopt;
}

StatusOr<PointCloud> ParseUploadedCloud(std::string_view bytes, CloudFileFormat format, uint64_t max_bytes) {
  if (bytes.empty()) return InvalidArgument(kWhere, "empty: the upload sent no bytes");
  if (format == CloudFileFormat::kDetect) {
    const std::optional<CloudFileFormat> detected = DetectCloudFormat(bytes);
    if (!detected) {
      return InvalidArgument("format", "not given, and the bytes are neither PLY (a first line \"ply\") nor PCD "
                                       "(\"# .PCD\", VERSION or FIELDS)");
    }
    format = *detected;
  }
  StatusOr<PointCloud> cloud = format == CloudFileFormat::kPly ? ParsePly(bytes, kWhere, max_bytes)
                                                               : ParsePcd(bytes, kWhere, max_bytes);
  if (!cloud.ok()) return AsUploadError(cloud.status());
  const size_t declared = cloud->size();
  DropHoles(*cloud);
  if (cloud->size() == 0) {
    return InvalidArgument(kWhere, declared == 0 ? "the file holds no points"
                                                 : "the file holds no points: all " + std::to_string(declared) +
                                                       " have NaN x, y and z (holes of an organised cloud)");
  }
  RETURN_IF_ERROR(CheckPositions(cloud->positions, "x, y, z"));
  if (cloud->Has(kFieldCleanPosition)) {
    RETURN_IF_ERROR(CheckPositions(cloud->clean_positions, "clean_x, clean_y, clean_z"));
  }
  return cloud;
}

}  // namespace vscan::service
