#include "icp_bench_data.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <Eigen/Geometry>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

namespace vscan::bench {
namespace {

const std::string kDir = std::string(VSCAN_DATA_DIR) + "/registration/";

[[noreturn]] void Die(const std::string& what) {
  std::fprintf(stderr, "icp_bench: %s\n", what.c_str());
  std::exit(1);
}

IcpCloud Load(const std::string& name) {
  // The files have no curvature field, which PCL would warn about for every load.
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  pcl::PointCloud<pcl::PointNormal> cloud;
  if (pcl::io::loadPCDFile(kDir + name, cloud) != 0) Die("cannot read " + kDir + name);
  IcpCloud out;
  for (const auto& p : cloud) {
    out.points.emplace_back(p.x, p.y, p.z);
    out.normals.emplace_back(p.normal_x, p.normal_y, p.normal_z);
  }
  return out;
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
