#include "reference_pair.h"

#include <fstream>
#include <utility>

#include <gtest/gtest.h>

#include "vscan/common/cloud_io.h"

namespace vscan::registration::testing {
namespace {

const std::string kDir = std::string(VSCAN_DATA_DIR) + "/registration/";

}  // namespace

Cloud ReadPcdWithNormals(const std::string& path) {
  StatusOr<PointCloud> read = ReadPcd(path);
  EXPECT_TRUE(read.ok()) << read.status().ToString();
  if (!read.ok()) return {};
  EXPECT_TRUE(read->Has(kFieldNormal)) << path << ": no normals";
  if (!read->Has(kFieldNormal)) return {};
  return {std::move(read->positions), std::move(read->normals)};
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
