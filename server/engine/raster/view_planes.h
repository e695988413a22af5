#pragma once
// The geometry of one raster scan, without GL: depth planes, the span of the range code, the
// projection from the pinhole intrinsics and the inverse of the depth mapping.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sensor/camera.h"
#include "vscan/common/pose.h"

namespace vscan::raster {

struct ViewPlanes {
  double near = 0, far = 0;              // depth z bounds of the frustum
  double near_range = 0, far_range = 0;  // camera-to-point distance bounds inside it
  bool empty = false;                    // nothing of the scene can be inside [camera.near, camera.far]
};

// With hug, planes just around the world box's corners along the view, inside the camera's near/far,
// and ranges bounded by the box's nearest and farthest points; otherwise the camera's own planes.
ViewPlanes PlanesForScene(const sensor::PinholeCamera& camera, const Pose3& world_from_sensor,
                          const Eigen::AlignedBox3d& world_box, bool hug);

// Length of the ray (x, y, 1) through the pixel centre farthest off axis.
double MaxRayLength(const sensor::PinholeCamera& camera);

// Sensor frame (x right, y down, z forward) to clip space. Window x is the image column
// coordinate and window y the row coordinate, so pixel centre (u + 0.5, v + 0.5) is the pixel
// RayThroughPixel(u, v) goes through, and GL's bottom-up row j read back is image row v = j.
// Window depth d in [0, 1]: d = f (z - n) / (z (f - n)), or d = n (f - z) / (z (f - n)) reversed.
// zero_to_one: clip z / w is d (glClipControl GL_ZERO_TO_ONE); otherwise it is 2 d - 1.
Eigen::Matrix4d ClipFromSensor(const sensor::PinholeCamera& camera, double near, double far, bool reversed,
                               bool zero_to_one);

// Depth z of window depth d: z = n f / (f - d (f - n)), or z = n f / (n + d (f - n)) reversed.
// (The first is the paper's z = 2 n f / (f + n - d' (f - n)) with d' = 2 d - 1 in [-1, 1].)
inline double LinearDepth(double d, double near, double far, bool reversed) {
  const double span = far - near;
  return near * far / (reversed ? near + d * span : far - d * span);
}

// dz/dd at depth z: how far one unit of window depth moves the depth there (the same both ways).
inline double DepthPerUnitD(double z, double near, double far) { return z * z * (far - near) / (near * far); }

}  // namespace vscan::raster
