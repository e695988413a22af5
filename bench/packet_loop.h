#pragma once
// The limit a scanner is measured against: a plain Embree loop over one pinhole frame in 4x4
// coherent packets (rtcIntersect16) on every core, counting hits and nothing else.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <embree3/rtcore.h>

#include "sensor/camera.h"
#include "vscan/common/pose.h"

namespace vscan::bench {

class PacketLoop {
 public:
  // The camera's width must be a multiple of 4.
  PacketLoop(RTCScene scene, const sensor::PinholeCamera& camera, const Pose3& world_from_sensor);
  // Casts the frame; returns the hits.
  uint64_t Frame() const;

 private:
  RTCScene scene_;
  sensor::PinholeCamera camera_;
  Eigen::Vector3f origin_;
  Eigen::Matrix3f rotation_;
  std::vector<float> row_y_;
  std::vector<float> packet_x_;  // per packet of 4 columns, the x of its 16 lanes
};

}  // namespace vscan::bench
