#pragma once
// Scans of the Stanford bunny (data/meshes/bunny) from views around it, cast with the project's ray
// caster, in the sensor frame and with known poses, for the multiview alignment tests.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::registration::testing {

struct BunnyView {
  Pose3 model_from_sensor = Pose3::Identity();
  std::vector<Eigen::Vector3f> points;  // sensor frame
};

// The middle of the bunny's bounding box (the model frame is the mesh's).
Eigen::Vector3d BunnyCentre();

// The sensor `distance` from the bunny's centre at an azimuth about the mesh's up axis (+y) and an
// elevation above its equator (degrees), looking at the centre.
Pose3 ViewAround(double azimuth_deg, double elevation_deg, double distance);

// A 320 x 240 depth scan with the given horizontal field of view (degrees), with Gaussian noise of
// noise_sigma (metres) on each coordinate.
BunnyView ScanBunny(const Pose3& model_from_sensor, double fov_deg, double noise_sigma, uint32_t seed);

// A rotation of angle_deg about a random axis through the bunny's centre followed by a move of
// shift (metres) in a random direction, applied in the model frame: a view's initial pose error.
Pose3 RandomError(double angle_deg, double shift, uint32_t seed);

// Where `estimate` puts the scan point that truly lies at the bunny's centre, against the centre
// (millimetres): the error of a view where it matters, at the object.
double CentreErrorMm(const Pose3& estimate, const Pose3& truth);

}  // namespace vscan::registration::testing
