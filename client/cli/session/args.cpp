#include "session/args.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>

#include "session/text_format.h"

namespace vscan::cli {
namespace {

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

std::vector<std::string> Split(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    out.push_back(Trim(text.substr(start, comma - start)));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

std::optional<double> ToDouble(const std::string& s) {
  double v = 0;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, v);
  if (s.empty() || ec != std::errc() || ptr != end) return std::nullopt;
  return v;
}

constexpr double kDegToRad = std::numbers::pi / 180.0;

}  // namespace

StatusOr<std::vector<double>> ParseNumbers(const std::string& text, size_t count, const std::string& option) {
  const auto parts = Split(text);
  if (parts.size() != count) {
    return InvalidArgument(option, "expected " + std::to_string(count) + " comma-separated numbers, got " +
                           std::to_string(parts.size()) + " in '" + text + "'");
  }
  std::vector<double> out;
  for (const auto& p : parts) {
    const auto v = ToDouble(p);
    if (!v) return InvalidArgument(option, "'" + p + "' is not a number");
    if (!std::isfinite(*v)) return InvalidArgument(option, "'" + p + "' is not finite");
    out.push_back(*v);
  }
  return out;
}

StatusOr<Eigen::Vector3d> ParseVector3(const std::string& text, const std::string& option) {
  ASSIGN_OR_RETURN(const auto v, ParseNumbers(text, 3, option));
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

StatusOr<v1::LengthUnit> ParseUnit(const std::string& text) {
  const std::string t = Lower(text);
  if (t == "m" || t == "metre" || t == "meter") return v1::LENGTH_UNIT_METRE;
  if (t == "cm" || t == "centimetre" || t == "centimeter") return v1::LENGTH_UNIT_CENTIMETRE;
  if (t == "mm" || t == "millimetre" || t == "millimeter") return v1::LENGTH_UNIT_MILLIMETRE;
  if (t == "in" || t == "inch") return v1::LENGTH_UNIT_INCH;
  if (t == "ft" || t == "foot" || t == "feet") return v1::LENGTH_UNIT_FOOT;
  return InvalidArgument("--unit", "unknown unit '" + text + "' (m, cm, mm, in, ft)");
}

StatusOr<v1::MeshFormat> ParseMeshFormat(const std::string& text) {
  const std::string t = Lower(text);
  if (t == "ply") return v1::MESH_FORMAT_PLY;
  if (t == "obj") return v1::MESH_FORMAT_OBJ;
  if (t == "stl") return v1::MESH_FORMAT_STL;
  return InvalidArgument("--format", "unknown mesh format '" + text + "' (ply, obj, stl)");
}

StatusOr<v1::CloudFormat> ParseCloudFormat(const std::string& text) {
  const std::string t = Lower(text);
  if (t == "ply") return v1::CLOUD_FORMAT_PLY;
  if (t == "pcd") return v1::CLOUD_FORMAT_PCD;
  return InvalidArgument("--format", "unknown cloud format '" + text + "' (ply, pcd)");
}

StatusOr<v1::CloudCamera> ParseCloudCamera(const std::string& text) {
  ASSIGN_OR_RETURN(const std::vector<double> v, ParseNumbers(text, 8, "--camera"));
  for (int i = 0; i < 2; ++i) {
    if (v[i] < 1 || v[i] > 1e6 || v[i] != std::floor(v[i])) {
      return InvalidArgument("--camera", "width and height must be whole numbers of pixels (1 to 1e6)");
    }
  }
  v1::CloudCamera camera;
  camera.set_width(static_cast<uint32_t>(v[0]));
  camera.set_height(static_cast<uint32_t>(v[1]));
  v1::Intrinsics* k = camera.mutable_intrinsics();
  k->set_fx(v[2]);
  k->set_fy(v[3]);
  k->set_cx(v[4]);
  k->set_cy(v[5]);
  camera.set_near(v[6]);
  camera.set_far(v[7]);
  return camera;
}

StatusOr<std::vector<v1::PointField>> ParseFields(const std::string& text) {
  std::vector<v1::PointField> out;
  const auto add = [&](v1::PointField f) {
    if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
  };
  for (const auto& raw : Split(text)) {
    const std::string f = Lower(raw);
    if (f == "position") {
      add(v1::POINT_FIELD_POSITION);
    } else if (f == "normal") {
      add(v1::POINT_FIELD_NORMAL);
    } else if (f == "range") {
      add(v1::POINT_FIELD_RANGE);
    } else if (f == "intensity") {
      add(v1::POINT_FIELD_INTENSITY);
    } else if (f == "instance" || f == "instance_id") {
      add(v1::POINT_FIELD_INSTANCE_ID);
    } else if (f == "pixel") {
      add(v1::POINT_FIELD_PIXEL);
    } else if (f == "clean" || f == "clean_position" || f == "clean-position") {
      add(v1::POINT_FIELD_CLEAN_POSITION);
    } else if (f == "incidence" || f == "incidence_angle" || f == "incidence-angle") {
      add(v1::POINT_FIELD_INCIDENCE_ANGLE);
    } else if (f == "status") {
      add(v1::POINT_FIELD_STATUS);
    } else if (f == "estimated-normal" || f == "estimated_normal") {
      add(v1::POINT_FIELD_ESTIMATED_NORMAL);
    } else if (f == "truth" || f == "ground-truth") {
      add(v1::POINT_FIELD_CLEAN_POSITION);
      add(v1::POINT_FIELD_INCIDENCE_ANGLE);
      add(v1::POINT_FIELD_STATUS);
    } else if (f == "all") {
      for (int v = v1::POINT_FIELD_POSITION; v <= v1::POINT_FIELD_PIXEL; ++v) add(static_cast<v1::PointField>(v));
    } else {
      return InvalidArgument("--fields", "unknown field '" + raw +
                             "' (position, normal, range, intensity, instance, pixel, all, clean, incidence, "
                             "status, truth, estimated-normal)");
    }
  }
  // Positions always travel; say so explicitly.
  if (std::find(out.begin(), out.end(), v1::POINT_FIELD_POSITION) == out.end()) {
    out.insert(out.begin(), v1::POINT_FIELD_POSITION);
  }
  return out;
}

StatusOr<v1::Frame> ParseFrame(const std::string& text) {
  const std::string t = Lower(text);
  if (t == "world") return v1::FRAME_WORLD;
  if (t == "sensor") return v1::FRAME_SENSOR;
  return InvalidArgument("--frame", "unknown frame '" + text + "' (world, sensor)");
}

StatusOr<v1::ScanBackend> ParseBackend(const std::string& text) {
  const std::string t = Lower(text);
  if (t == "raycast") return v1::SCAN_BACKEND_RAYCAST;
  if (t == "depth" || t == "raster-depth") return v1::SCAN_BACKEND_RASTER_DEPTH;
  if (t == "colour" || t == "color" || t == "raster-colour") return v1::SCAN_BACKEND_RASTER_COLOUR;
  return InvalidArgument("--backend", "unknown backend '" + text + "' (raycast, depth, colour)");
}

Eigen::Matrix3d RotationFromRpyDegrees(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw * kDegToRad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch * kDegToRad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll * kDegToRad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

StatusOr<PoseParts> ParsePoseArgs(const PoseArgs& args) {
  const int rotations = !args.rpy.empty() + !args.quat.empty() + !args.matrix.empty();
  if (rotations > 1) return InvalidArgument("--rpy, --quat and --matrix are mutually exclusive");
  if (!args.matrix.empty() && !args.position.empty()) {
    return InvalidArgument("--matrix already holds the translation; drop --position");
  }
  PoseParts parts;
  if (!args.position.empty()) {
    ASSIGN_OR_RETURN(parts.translation, ParseVector3(args.position, "--position"));
  }
  if (!args.rpy.empty()) {
    ASSIGN_OR_RETURN(const auto v, ParseNumbers(args.rpy, 3, "--rpy"));
    parts.rotation = RotationFromRpyDegrees(v[0], v[1], v[2]);
  }
  if (!args.quat.empty()) {
    ASSIGN_OR_RETURN(const auto v, ParseNumbers(args.quat, 4, "--quat"));
    ASSIGN_OR_RETURN(const Pose3 p,
                     PoseFromQuaternion(Eigen::Vector3d::Zero(), Eigen::Quaterniond(v[0], v[1], v[2], v[3]), "--quat"));
    parts.rotation = p.linear();
  }
  if (!args.matrix.empty()) {
    ASSIGN_OR_RETURN(const auto v, ParseNumbers(args.matrix, 16, "--matrix"));
    const Eigen::Matrix4d m = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(v.data());
    ASSIGN_OR_RETURN(const Pose3 p, PoseFromMatrix(m, "--matrix"));
    parts.rotation = p.linear();
    parts.translation = p.translation();
  }
  return parts;
}

Pose3 ApplyPoseParts(const PoseParts& parts, const Pose3& base) {
  Pose3 out = base;
  if (parts.rotation) out.linear() = *parts.rotation;
  if (parts.translation) out.translation() = *parts.translation;
  return out;
}

}  // namespace vscan::cli
