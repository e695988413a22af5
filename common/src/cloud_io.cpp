#include "vscan/common/cloud_io.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include <unistd.h>

namespace vscan {
namespace {

static_assert(std::endian::native == std::endian::little, "binary files are written in native little-endian");

// One scalar column of the interleaved record (4-byte float/uint or 1-byte uchar), with its names
// in each format.
struct Column {
  const char* ply_name;
  const char* pcd_name;
  bool is_float;
  const char* base;  // first value of this column; stride between points is `step` bytes
  size_t step;
  size_t size = 4;
};

std::vector<Column> Columns(const PointCloud& cloud) {
  std::vector<Column> cols;
  const auto add_vec3 = [&](const std::vector<Eigen::Vector3f>& v, const char* const ply[3],
                            const char* const pcd[3]) {
    for (int i = 0; i < 3; ++i) {
      cols.push_back({ply[i], pcd[i], true, reinterpret_cast<const char*>(v.data()) + 4 * i, 12});
    }
  };
  static const char* const kXyz[3] = {"x", "y", "z"};
  static const char* const kNormPly[3] = {"nx", "ny", "nz"};
  static const char* const kNormPcd[3] = {"normal_x", "normal_y", "normal_z"};
  static const char* const kClean[3] = {"clean_x", "clean_y", "clean_z"};
  static const char* const kEstPly[3] = {"enx", "eny", "enz"};
  static const char* const kEstPcd[3] = {"est_normal_x", "est_normal_y", "est_normal_z"};
  add_vec3(cloud.positions, kXyz, kXyz);
  if (cloud.Has(kFieldNormal)) add_vec3(cloud.normals, kNormPly, kNormPcd);
  if (cloud.Has(kFieldRange))
    cols.push_back({"range", "range", true, reinterpret_cast<const char*>(cloud.ranges.data()), 4});
  if (cloud.Has(kFieldIntensity))
    cols.push_back({"intensity", "intensity", true, reinterpret_cast<const char*>(cloud.intensities.data()), 4});
  if (cloud.Has(kFieldInstanceId))
    cols.push_back({"instance", "instance", false, reinterpret_cast<const char*>(cloud.instance_ids.data()), 4});
  if (cloud.Has(kFieldPixel))
    cols.push_back({"pixel", "pixel", false, reinterpret_cast<const char*>(cloud.pixels.data()), 4});
  if (cloud.Has(kFieldCleanPosition)) add_vec3(cloud.clean_positions, kClean, kClean);
  if (cloud.Has(kFieldIncidence))
    cols.push_back({"incidence", "incidence", true, reinterpret_cast<const char*>(cloud.incidence_angles.data()), 4});
  if (cloud.Has(kFieldStatus))
    cols.push_back({"status", "status", false, reinterpret_cast<const char*>(cloud.statuses.data()), 1, 1});
  if (cloud.Has(kFieldEstimatedNormal)) add_vec3(cloud.estimated_normals, kEstPly, kEstPcd);
  return cols;
}

size_t RecordBytes(const std::vector<Column>& cols) {
  size_t bytes = 0;
  for (const Column& c : cols) bytes += c.size;
  return bytes;
}

const char* PlyType(const Column& c) {
  if (c.size == 1) return "uchar";
  return c.is_float ? "float" : "uint";
}

Status CheckConsistent(const PointCloud& cloud) {
  const size_t n = cloud.size();
  const auto check = [&](PointFields f, size_t got, const char* name) -> Status {
    if (cloud.Has(f) && got != n) {
      return InvalidArgument(std::string("cloud.") + name + ": has " + std::to_string(got) + " values for " +
                             std::to_string(n) + " points");
    }
    return Status::Ok();
  };
  RETURN_IF_ERROR(check(kFieldNormal, cloud.normals.size(), "normals"));
  RETURN_IF_ERROR(check(kFieldRange, cloud.ranges.size(), "ranges"));
  RETURN_IF_ERROR(check(kFieldIntensity, cloud.intensities.size(), "intensities"));
  RETURN_IF_ERROR(check(kFieldInstanceId, cloud.instance_ids.size(), "instance_ids"));
  RETURN_IF_ERROR(check(kFieldPixel, cloud.pixels.size(), "pixels"));
  RETURN_IF_ERROR(check(kFieldCleanPosition, cloud.clean_positions.size(), "clean_positions"));
  RETURN_IF_ERROR(check(kFieldIncidence, cloud.incidence_angles.size(), "incidence_angles"));
  RETURN_IF_ERROR(check(kFieldStatus, cloud.statuses.size(), "statuses"));
  return check(kFieldEstimatedNormal, cloud.estimated_normals.size(), "estimated_normals");
}

// Interleaves points [begin, begin + count) into out, one record after another.
void PackRecords(const std::vector<Column>& cols, size_t begin, size_t count, char* out) {
  for (size_t i = begin; i < begin + count; ++i) {
    for (const Column& c : cols) {
      std::memcpy(out, c.base + i * c.step, c.size);
      out += c.size;
    }
  }
}

std::string PlyHeader(const std::vector<Column>& cols, size_t n) {
  std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) + "\n";
  for (const Column& c : cols) {
    header += std::string("property ") + PlyType(c) + " " + c.ply_name + "\n";
  }
  header += "end_header\n";
  return header;
}

std::string ErrnoText() { return std::strerror(errno); }

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// Writes header + interleaved records to a temporary file beside path, then renames it into place.
Status WriteAtomically(const std::string& path, const std::string& header, const std::vector<Column>& cols,
                       size_t n) {
  static std::atomic<unsigned> counter{0};
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    const int err = errno;
    const std::string msg = path + ": cannot create: " + std::strerror(err);
    return err == ENOENT ? NotFound(msg) : FailedPrecondition(msg);
  }
  const auto fail = [&](const std::string& what) {
    const std::string msg = path + ": " + what + ": " + ErrnoText();
    std::fclose(f);
    std::remove(tmp.c_str());
    return DataLoss(msg);
  };
  if (std::fwrite(header.data(), 1, header.size(), f) != header.size()) return fail("short write");

  const size_t record = RecordBytes(cols);
  constexpr size_t kBlockPoints = 16384;
  std::vector<char> block(std::min(n, kBlockPoints) * record);
  for (size_t begin = 0; begin < n; begin += kBlockPoints) {
    const size_t count = std::min(kBlockPoints, n - begin);
    PackRecords(cols, begin, count, block.data());
    if (std::fwrite(block.data(), 1, count * record, f) != count * record) return fail("short write");
  }
  if (std::fflush(f) != 0) return fail("short write");
  if (::fsync(::fileno(f)) != 0) return fail("fsync");
  if (std::fclose(f) != 0) {
    std::remove(tmp.c_str());
    return DataLoss(path + ": close: " + ErrnoText());
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string msg = path + ": rename: " + ErrnoText();
    std::remove(tmp.c_str());
    return DataLoss(msg);
  }
  return Status::Ok();
}

}  // namespace

Status WritePly(const PointCloud& cloud, const std::string& path) {
  RETURN_IF_ERROR(CheckConsistent(cloud));
  const auto cols = Columns(cloud);
  return WriteAtomically(path, PlyHeader(cols, cloud.size()), cols, cloud.size());
}

StatusOr<std::string> EncodePly(const PointCloud& cloud) {
  RETURN_IF_ERROR(CheckConsistent(cloud));
  const auto cols = Columns(cloud);
  std::string bytes = PlyHeader(cols, cloud.size());
  const size_t header = bytes.size();
  bytes.resize(header + cloud.size() * RecordBytes(cols));
  PackRecords(cols, 0, cloud.size(), bytes.data() + header);
  return bytes;
}

Status WritePcd(const PointCloud& cloud, const std::string& path) {
  RETURN_IF_ERROR(CheckConsistent(cloud));
  const auto cols = Columns(cloud);
  std::string fields, sizes, types, counts;
  for (const Column& c : cols) {
    fields += std::string(" ") + c.pcd_name;
    sizes += " " + std::to_string(c.size);
    types += c.is_float ? " F" : " U";
    counts += " 1";
  }
  const std::string n = std::to_string(cloud.size());
  const std::string header = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS" + fields +
                             "\nSIZE" + sizes + "\nTYPE" + types + "\nCOUNT" + counts + "\nWIDTH " + n +
                             "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA binary\n";
  return WriteAtomically(path, header, cols, cloud.size());
}

Status WriteCloud(const PointCloud& cloud, const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext == ".ply") return WritePly(cloud, path);
  if (ext == ".pcd") return WritePcd(cloud, path);
  return InvalidArgument(path + ": unknown point cloud extension '" + ext + "' (use .ply or .pcd)");
}

StatusOr<PointCloud> ReadCloud(const std::string& path) {
  const std::string ext = LowerExtension(path);
  if (ext == ".ply") return ReadPly(path);
  if (ext == ".pcd") return ReadPcd(path);
  return InvalidArgument(path + ": unknown point cloud extension '" + ext + "' (use .ply or .pcd)");
}

}  // namespace vscan
