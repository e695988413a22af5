#include "vscan/common/cloud_io.h"

#include <bit>
#include <cstring>
#include <filesystem>
#include <optional>
#include <vector>

#include "cloud_columns.h"
#include "vscan/common/cloud_file_writer.h"

namespace vscan {
namespace {

static_assert(std::endian::native == std::endian::little, "binary files are written in native little-endian");

Status WriteWhole(const PointCloud& cloud, const std::string& path, CloudFileFormat format) {
  RETURN_IF_ERROR(cloud_file::CheckConsistent(cloud));
  ASSIGN_OR_RETURN(CloudFileWriter writer, CloudFileWriter::Open(path, format, cloud.fields, cloud.size()));
  RETURN_IF_ERROR(writer.Append(cloud));
  return writer.Finish();
}

Status UnknownExtension(const std::string& path) {
  return InvalidArgument(path + ": unknown point cloud extension '" +
                         std::filesystem::path(path).extension().string() + "' (use .ply or .pcd)");
}

}  // namespace

Status WritePly(const PointCloud& cloud, const std::string& path) {
  return WriteWhole(cloud, path, CloudFileFormat::kPly);
}

Status WritePcd(const PointCloud& cloud, const std::string& path) {
  return WriteWhole(cloud, path, CloudFileFormat::kPcd);
}

Status WriteCloud(const PointCloud& cloud, const std::string& path) {
  const std::optional<CloudFileFormat> format = CloudFileFormatOf(path);
  if (!format) return UnknownExtension(path);
  return WriteWhole(cloud, path, *format);
}

StatusOr<std::string> EncodePly(const PointCloud& cloud) {
  RETURN_IF_ERROR(cloud_file::CheckConsistent(cloud));
  const auto cols = cloud_file::Columns(cloud);
  std::string bytes = cloud_file::PlyHeader(cols, cloud.size(), std::nullopt);
  char* out = nullptr;
  {
    const size_t header = bytes.size();
    bytes.resize(header + cloud.size() * cloud_file::RecordBytes(cols));
    out = bytes.data() + header;
  }
  for (size_t i = 0; i < cloud.size(); ++i) {
    for (const cloud_file::Column& c : cols) {
      std::memcpy(out, c.base + i * c.step, c.size);
      out += c.size;
    }
  }
  return bytes;
}

StatusOr<PointCloud> ReadCloud(const std::string& path) {
  const std::optional<CloudFileFormat> format = CloudFileFormatOf(path);
  if (!format) return UnknownExtension(path);
  return *format == CloudFileFormat::kPly ? ReadPly(path) : ReadPcd(path);
}

}  // namespace vscan
