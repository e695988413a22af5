#include "vscan/common/organized_pcd.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>
#include <vector>

#include "cloud_columns.h"

namespace vscan {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

Status WriteFileAtomically(const std::string& path, const std::string& bytes) {
  static std::atomic<unsigned> counter{0};
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (!file) {
    const int err = errno;
    const std::string msg = path + ": cannot create: " + std::strerror(err);
    return err == ENOENT ? NotFound(msg) : FailedPrecondition(msg);
  }
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size() && std::fflush(file) == 0 &&
                       ::fsync(::fileno(file)) == 0;
  const std::string error = std::strerror(errno);
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed || std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    return DataLoss(path + ": write failed: " + error);
  }
  return Status::Ok();
}

}  // namespace

StatusOr<PointCloud> OrganizeByPixel(const PointCloud& cloud, uint32_t width, uint32_t height) {
  if (!cloud.Has(kFieldPixel)) return InvalidArgument("cloud.pixels: an organised cloud needs each point's pixel");
  if (width == 0 || height == 0) {
    return InvalidArgument("image: " + std::to_string(width) + " x " + std::to_string(height) + " pixels is empty");
  }
  RETURN_IF_ERROR(cloud_file::CheckConsistent(cloud));
  const size_t pixels = size_t{width} * height;
  PointCloud grid;
  grid.fields = cloud.fields;
  grid.Resize(pixels);
  const Eigen::Vector3f nan3(kNaN, kNaN, kNaN);
  const auto fill = [](auto& v, auto value) { std::fill(v.begin(), v.end(), value); };
  fill(grid.positions, nan3);
  fill(grid.normals, nan3);
  fill(grid.ranges, kNaN);
  fill(grid.intensities, kNaN);
  fill(grid.instance_ids, 0u);
  for (size_t i = 0; i < grid.pixels.size(); ++i) grid.pixels[i] = static_cast<uint32_t>(i);
  fill(grid.clean_positions, nan3);
  fill(grid.incidence_angles, kNaN);
  fill(grid.statuses, uint8_t{0});
  fill(grid.estimated_normals, nan3);

  std::vector<bool> taken(pixels, false);
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint32_t p = cloud.pixels[i];
    if (p >= pixels) {
      return InvalidArgument("cloud.pixels[" + std::to_string(i) + "]: pixel " + std::to_string(p) +
                             " lies outside the " + std::to_string(width) + " x " + std::to_string(height) + " image");
    }
    if (taken[p]) {
      return InvalidArgument("cloud.pixels[" + std::to_string(i) + "]: pixel " + std::to_string(p) +
                             " already holds a point");
    }
    taken[p] = true;
    grid.positions[p] = cloud.positions[i];
    if (cloud.Has(kFieldNormal)) grid.normals[p] = cloud.normals[i];
    if (cloud.Has(kFieldRange)) grid.ranges[p] = cloud.ranges[i];
    if (cloud.Has(kFieldIntensity)) grid.intensities[p] = cloud.intensities[i];
    if (cloud.Has(kFieldInstanceId)) grid.instance_ids[p] = cloud.instance_ids[i];
    if (cloud.Has(kFieldCleanPosition)) grid.clean_positions[p] = cloud.clean_positions[i];
    if (cloud.Has(kFieldIncidence)) grid.incidence_angles[p] = cloud.incidence_angles[i];
    if (cloud.Has(kFieldStatus)) grid.statuses[p] = cloud.statuses[i];
    if (cloud.Has(kFieldEstimatedNormal)) grid.estimated_normals[p] = cloud.estimated_normals[i];
  }
  return grid;
}

Status WriteOrganizedPcd(const PointCloud& cloud, const RangeImageLayout& image, const std::string& path) {
  ASSIGN_OR_RETURN(const PointCloud grid, OrganizeByPixel(cloud, image.width, image.height));
  const Eigen::Vector3d t = image.viewpoint.translation();
  const Eigen::Quaterniond q(image.viewpoint.rotation());
  cloud_file::PcdImage header_image;
  header_image.width = image.width;
  header_image.height = image.height;
  const double viewpoint[7] = {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()};
  std::copy(std::begin(viewpoint), std::end(viewpoint), std::begin(header_image.viewpoint));
  const auto cols = cloud_file::Columns(grid);
  std::string bytes = cloud_file::PcdHeader(cols, header_image);
  const size_t header = bytes.size();
  bytes.resize(header + grid.size() * cloud_file::RecordBytes(cols));
  char* out = bytes.data() + header;
  for (size_t i = 0; i < grid.size(); ++i) {
    for (const cloud_file::Column& c : cols) {
      std::memcpy(out, c.base + i * c.step, c.size);
      out += c.size;
    }
  }
  return WriteFileAtomically(path, bytes);
}

}  // namespace vscan
