#include "cloud_columns.h"

#include <cstdio>

namespace vscan::cloud_file {
namespace {

const char* PlyType(const Column& c) {
  if (c.size == 1) return "uchar";
  return c.is_float ? "float" : "int";
}

}  // namespace

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

std::string PlyHeader(const std::vector<Column>& cols, uint64_t points, std::optional<size_t> pad) {
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  if (pad) header += "comment" + std::string(*pad, ' ') + "\n";
  header += "element vertex " + std::to_string(points) + "\n";
  for (const Column& c : cols) header += std::string("property ") + PlyType(c) + " " + c.ply_name + "\n";
  return header + "end_header\n";
}

namespace {

std::string PcdHeaderWith(const std::vector<Column>& cols, uint64_t width, uint64_t height,
                          const std::string& viewpoint, size_t pad) {
  std::string fields, sizes, types, counts;
  for (const Column& c : cols) {
    fields += std::string(" ") + c.pcd_name;
    sizes += " " + std::to_string(c.size);
    // The 1-byte status stays unsigned (uchar in PLY); 4-byte integers are signed as in the PLY.
    types += c.is_float ? " F" : c.size == 1 ? " U" : " I";
    counts += " 1";
  }
  return "# .PCD v0.7 - Point Cloud Data file format" + std::string(pad, ' ') + "\nVERSION 0.7\nFIELDS" + fields +
         "\nSIZE" + sizes + "\nTYPE" + types + "\nCOUNT" + counts + "\nWIDTH " + std::to_string(width) +
         "\nHEIGHT " + std::to_string(height) + "\nVIEWPOINT " + viewpoint + "\nPOINTS " +
         std::to_string(width * height) + "\nDATA binary\n";
}

}  // namespace

std::string PcdHeader(const std::vector<Column>& cols, uint64_t points, std::optional<size_t> pad) {
  return PcdHeaderWith(cols, points, 1, "0 0 0 1 0 0 0", pad.value_or(0));
}

std::string PcdHeader(const std::vector<Column>& cols, const PcdImage& image) {
  std::string viewpoint;
  for (const double v : image.viewpoint) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.9g", v);
    viewpoint += (viewpoint.empty() ? "" : " ") + std::string(text);
  }
  return PcdHeaderWith(cols, image.width, image.height, viewpoint, 0);
}

}  // namespace vscan::cloud_file
