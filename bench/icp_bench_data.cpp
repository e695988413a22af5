#include "icp_bench_data.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <utility>

#include <Eigen/Geometry>

#include "vscan/common/cloud_io.h"

namespace vscan::bench {
namespace {

const std::string kDir = std::string(VSCAN_DATA_DIR) + "/registration/";

[[noreturn]] void Die(const std::string& what) {
  std::fprintf(stderr, "icp_bench: %s\n", what.c_str());
  std::exit(1);
}

IcpCloud Load(const std::string& name) {
  StatusOr<PointCloud> cloud = ReadPcd(kDir + name);
  if (!cloud.ok()) Die(cloud.status().ToString());
  if (!cloud->Has(kFieldNormal)) Die(kDir + name + " has no normals");
  return {std::move(cloud->positions), std::move(cloud->normals)};
}

}  // namespace

const IcpPair& ReferencePair() {
  static const IcpPair pair = [] {
    IcpPair p;
    p.source = Load("src_100k.pcd");
    p.target = Load("tgt_100k.pcd");
    std::ifstream in(kDir + "T_gt_src_from_tgt.txt");
    Eigen::Matrix4d source_from_target;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) in >> source_from_target(r, c);
    }
    if (!in) Die("cannot read " + kDir + "T_gt_src_from_tgt.txt");
    p.target_from_source = Eigen::Isometry3d(source_from_target).inverse().matrix();
    return p;
  }();
  return pair;
}

double RotationErrorDeg(const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth) {
  const Eigen::Matrix3d delta = estimate.topLeftCorner<3, 3>().transpose() * truth.topLeftCorner<3, 3>();
  return Eigen::AngleAxisd(delta).angle() * 180.0 / EIGEN_PI;
}

double TranslationErrorMm(const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth) {
  return (estimate.topRightCorner<3, 1>() - truth.topRightCorner<3, 1>()).norm() * 1000.0;
}

}  // namespace vscan::bench
