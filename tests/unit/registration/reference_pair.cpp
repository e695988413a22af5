#include "reference_pair.h"

#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace vscan::registration::testing {
namespace {

const std::string kDir = std::string(VSCAN_DATA_DIR) + "/registration/";

}  // namespace

Cloud ReadPcdWithNormals(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << path;
  std::string line;
  size_t count = 0;
  bool fields_ok = false, binary = false;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "FIELDS") fields_ok = line == "FIELDS x y z normal_x normal_y normal_z";
    if (key == "POINTS") words >> count;
    if (key == "DATA") {
      binary = line == "DATA binary";
      break;
    }
  }
  EXPECT_TRUE(fields_ok && binary && count > 0) << path << ": unexpected PCD layout";
  if (!fields_ok || !binary) return {};
  std::vector<float> raw(count * 6);
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size() * sizeof(float)));
  EXPECT_TRUE(in) << path << ": truncated";
  Cloud cloud;
  cloud.points.resize(count);
  cloud.normals.resize(count);
  for (size_t i = 0; i < count; ++i) {
    cloud.points[i] = Eigen::Vector3f(raw[6 * i], raw[6 * i + 1], raw[6 * i + 2]);
    cloud.normals[i] = Eigen::Vector3f(raw[6 * i + 3], raw[6 * i + 4], raw[6 * i + 5]);
  }
  return cloud;
}

const ReferencePair& LoadReferencePair() {
  static const ReferencePair pair = [] {
    ReferencePair p;
    p.source = ReadPcdWithNormals(kDir + "src_100k.pcd");
    p.target = ReadPcdWithNormals(kDir + "tgt_100k.pcd");
    std::ifstream in(kDir + "T_gt_src_from_tgt.txt");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) in >> m(r, c);
    }
    EXPECT_TRUE(in) << "T_gt_src_from_tgt.txt";
    p.target_from_source = Pose3(m).inverse();
    return p;
  }();
  return pair;
}

}  // namespace vscan::registration::testing
