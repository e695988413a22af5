// Writes the PCL-made clouds that tests/integration/data/pcl holds (uploads of files PCL wrote):
//   vscan_pcl_cloud_files DIR
// 200 points of PointXYZINormal in every encoding PCL writes, and an organised 8 x 6 PointXYZ range
// image with NaN holes in each PCD encoding. The values are a function of the index (see README).

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  pcl::PointCloud<pcl::PointXYZINormal> cloud;
  for (int i = 0; i < 200; ++i) {
    pcl::PointXYZINormal p;
    const float a = 0.05f * static_cast<float>(i);
    p.x = 0.1f * std::cos(a);
    p.y = 0.1f * std::sin(a);
    p.z = 0.5f + 0.001f * static_cast<float>(i);
    p.intensity = 0.005f * static_cast<float>(i);
    p.normal_x = std::cos(a);
    p.normal_y = std::sin(a);
    p.normal_z = 0.0f;
    p.curvature = 0.0f;
    cloud.push_back(p);
  }
  pcl::PointCloud<pcl::PointXYZ> image(8, 6);
  for (uint32_t v = 0; v < 6; ++v) {
    for (uint32_t u = 0; u < 8; ++u) {
      const bool hole = (u + v) % 3 == 0;
      const float nan = std::numeric_limits<float>::quiet_NaN();
      image.at(u, v) = hole ? pcl::PointXYZ(nan, nan, nan)
                            : pcl::PointXYZ(0.01f * static_cast<float>(u), 0.01f * static_cast<float>(v), 0.75f);
    }
  }
  image.is_dense = false;
  image.sensor_origin_ = Eigen::Vector4f(0.0f, 0.1f, 0.5f, 0.0f);
  pcl::PCDWriter pcd;
  pcl::PLYWriter ply;
  const bool ok = pcd.writeASCII(dir + "/pcl_ascii.pcd", cloud) == 0 && pcd.writeBinary(dir + "/pcl_binary.pcd", cloud) == 0 &&
                  pcd.writeBinaryCompressed(dir + "/pcl_compressed.pcd", cloud) == 0 &&
                  ply.write(dir + "/pcl_ascii.ply", cloud, false) == 0 && ply.write(dir + "/pcl_binary.ply", cloud, true) == 0 &&
                  pcd.writeASCII(dir + "/pcl_organised_ascii.pcd", image) == 0 &&
                  pcd.writeBinary(dir + "/pcl_organised_binary.pcd", image) == 0 &&
                  pcd.writeBinaryCompressed(dir + "/pcl_organised_compressed.pcd", image) == 0;
  return ok ? 0 : 1;
}
