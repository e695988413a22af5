#pragma once
// Parsing of command-line values ("x,y,z", units, field lists, poses) into wire types.
// Every parser returns INVALID_ARGUMENT naming the option it rejects.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"
#include "vscan/common/status.h"
#include "vscan/v1/cloud.pb.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/scan.pb.h"
#include "vscan/v1/scene.pb.h"

namespace vscan::cli {

// Exactly count comma-separated finite numbers.
StatusOr<std::vector<double>> ParseNumbers(const std::string& text, size_t count, const std::string& option);
StatusOr<Eigen::Vector3d> ParseVector3(const std::string& text, const std::string& option);

// m, cm, mm, in, ft (and their long names).
StatusOr<v1::LengthUnit> ParseUnit(const std::string& text);
// ply, obj, stl.
StatusOr<v1::MeshFormat> ParseMeshFormat(const std::string& text);
// ply, pcd.
StatusOr<v1::CloudFormat> ParseCloudFormat(const std::string& text);
// width,height,fx,fy,cx,cy,near,far (pixels and metres).
StatusOr<v1::CloudCamera> ParseCloudCamera(const std::string& text);
// Comma-separated: position, normal, range, intensity, instance, pixel, or "all" (those six);
// ground truth: clean, incidence, status, or "truth" (those three); estimated-normal.
StatusOr<std::vector<v1::PointField>> ParseFields(const std::string& text);
// world or sensor.
StatusOr<v1::Frame> ParseFrame(const std::string& text);
// raycast, depth or colour.
StatusOr<v1::ScanBackend> ParseBackend(const std::string& text);

// The pose options of `object add|move`; empty strings were not given.
struct PoseArgs {
  std::string position;  // x,y,z
  std::string rpy;       // roll,pitch,yaw in degrees, applied as Rz(yaw) * Ry(pitch) * Rx(roll)
  std::string quat;      // w,x,y,z
  std::string matrix;    // 16 values, row-major
};

// What the options fix; a matrix fixes both parts.
struct PoseParts {
  std::optional<Eigen::Vector3d> translation;
  std::optional<Eigen::Matrix3d> rotation;
  bool empty() const { return !translation && !rotation; }
  bool complete() const { return translation && rotation; }
};

StatusOr<PoseParts> ParsePoseArgs(const PoseArgs& args);
// base with the parts the options fixed replaced.
Pose3 ApplyPoseParts(const PoseParts& parts, const Pose3& base);
Eigen::Matrix3d RotationFromRpyDegrees(double roll, double pitch, double yaw);

// The options of `vscan scan`; empty strings / nullopt were not given.
struct ScanArgs {
  std::string scene_id;
  std::string preset;
  uint32_t width = 640;
  uint32_t height = 480;
  std::optional<double> hfov_deg;
  std::string intrinsics;  // fx,fy,cx,cy
  double near = 0.05;
  double far = 10.0;
  std::string lighting;  // power,constant,linear,quadratic
  std::string eye, target, up = "0,0,1";
  std::string pose_matrix;
  std::string frame = "world";
  std::string fields;
  std::string backend = "raycast";
  std::optional<double> table_angle_deg;
  std::optional<uint32_t> chunk_kib;
  uint64_t seed = 0;
  // A robot-held sensor instead of --eye/--target: the mount and its joint positions q1,q2,...
  std::string mount;
  std::string joints;
  bool encoder_noise = false;
  // Measurement noise and artefacts; any of them given sends a NoiseSpec (replacing a preset's).
  std::string noise_sigma;  // a[,b[,c]]: sigma = a + b z + c z^2 metres
  bool along_ray = false;
  std::optional<double> depth_step_m;
  std::optional<double> min_intensity;
  std::optional<double> outlier_rate;
  std::optional<double> outlier_angle_deg;
  std::optional<double> outlier_origin_m;
  std::optional<double> grazing_limit_deg;
  bool flying_pixels = false;
  std::optional<double> flying_pixel_edge_m;
  bool include_rejected = false;
  // "on" (the defaults) or key=value,... with ReturnedLight's field names (emitter_w_per_sr=2,...).
  std::optional<std::string> returned_light;
  // Set when --estimate-normals was given; 0 is the server's default k.
  std::optional<uint32_t> estimate_normals_k;
  std::optional<double> normal_max_distance;
};

StatusOr<v1::ScanRequest> BuildScanRequest(const ScanArgs& args);

// --returned-light: "on" (the defaults) or key=value,... naming vscan.v1.ReturnedLight's fields.
Status FillReturnedLight(const std::string& text, v1::ReturnedLight* light);

}  // namespace vscan::cli
