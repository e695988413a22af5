// PCL's FPFH + SampleConsensusPrerejective + ICP pipeline (localization_pcl.cpp) on one scan file and
// one part file, for bin_localization.py to run beside vscan's localizer on the same scans.
// Usage: localization_pcl_peer SCAN.ply PART.(stl|ply) METRES_PER_UNIT MAX_INSTANCES VX VY VZ [VOXEL]
//   SCAN.ply: x y z in metres (normals, if any, are not used: PCL estimates its own);
//   METRES_PER_UNIT: the part file's unit times its scale; VX VY VZ: the sensor's position, towards
//   which scan normals are turned; VOXEL (m): by default the part's bounding-box diagonal / 50, or its
//   middle extent / 10 when smaller, vscan's own rule.
// Prints one JSON object: the voxel, the seconds the pipeline took (after reading the files) and the
// instances, each with world_from_part (16 values, row-major; the part file's frame at its scale)
// and its score.
#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "geometry/mesh_import.h"
#include "localization/model_samples.h"
#include "localization_pcl.h"
#include "vscan/common/cloud_io.h"

namespace vscan::bench {
namespace {

constexpr size_t kModelSamples = 20000;
constexpr size_t kMaxInstances = 1000;

int Fail(const std::string& message) {
  std::fprintf(stderr, "localization_pcl_peer: %s\n", message.c_str());
  return 1;
}

bool ParseDouble(const char* text, double& value) {
  char* end = nullptr;
  value = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(value);
}

double VoxelFromPart(const TriangleMesh& mesh) {
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  std::array<float, 3> extent{hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z()};
  std::sort(extent.begin(), extent.end());
  return std::min(static_cast<double>((hi - lo).norm()) / 50, static_cast<double>(extent[1]) / 10);
}

geometry::MeshFileFormat FormatOf(const std::string& path) {
  std::string ext = path.substr(path.find_last_of('.') + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == "stl") return geometry::MeshFileFormat::kStl;
  if (ext == "ply") return geometry::MeshFileFormat::kPly;
  if (ext == "obj") return geometry::MeshFileFormat::kObj;
  return geometry::MeshFileFormat::kAuto;
}

int Main(int argc, char** argv) {
  if (argc != 8 && argc != 9) {
    return Fail("usage: localization_pcl_peer SCAN.ply PART.(stl|ply) METRES_PER_UNIT MAX_INSTANCES VX VY VZ [VOXEL]");
  }
  double metres_per_unit = 0, max_instances = 0, voxel = 0;
  Eigen::Vector3d viewpoint;
  if (!ParseDouble(argv[3], metres_per_unit) || metres_per_unit <= 0) return Fail("METRES_PER_UNIT: finite, > 0");
  if (!ParseDouble(argv[4], max_instances) || max_instances < 1 || max_instances > kMaxInstances ||
      max_instances != std::floor(max_instances)) {
    return Fail("MAX_INSTANCES: a whole number from 1 to 1000");
  }
  for (int i = 0; i < 3; ++i) {
    if (!ParseDouble(argv[5 + i], viewpoint[i])) return Fail("VX VY VZ: finite numbers");
  }
  if (argc == 9 && (!ParseDouble(argv[8], voxel) || voxel <= 0)) return Fail("VOXEL: finite, > 0");

  const auto scan = ReadPly(argv[1]);
  if (!scan.ok()) return Fail(scan.status().ToString());
  std::ifstream in(argv[2], std::ios::binary);
  if (!in) return Fail(std::string("cannot open ") + argv[2]);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto part = geometry::ImportMesh(bytes, FormatOf(argv[2]), metres_per_unit);
  if (!part.ok()) return Fail(part.status().ToString());
  if (voxel == 0) voxel = VoxelFromPart(*part);

  std::vector<Eigen::Vector3f> points;
  points.reserve(scan->positions.size());
  for (const auto& p : scan->positions) {
    if (p.allFinite()) points.push_back(p);
  }
  const auto start = std::chrono::steady_clock::now();
  const localization::ModelSamples samples = localization::SampleModel(*part, kModelSamples, 1);
  const auto found = PclLocalize(samples.points, samples.normals, points, viewpoint.cast<float>(), voxel,
                                 static_cast<size_t>(max_instances));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("{\"voxel\": %.9g, \"seconds\": %.6f, \"points\": %zu, \"instances\": [", voxel, seconds, points.size());
  for (size_t i = 0; i < found.size(); ++i) {
    const Eigen::Matrix4d m = found[i].world_from_part.matrix();
    std::printf("%s\n {\"score\": %.9g, \"world_from_part\": [", i == 0 ? "" : ",", found[i].score);
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) std::printf("%s%.17g", r == 0 && c == 0 ? "" : ", ", m(r, c));
    }
    std::printf("]}");
  }
  std::printf("]}\n");
  return 0;
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) { return vscan::bench::Main(argc, argv); }
