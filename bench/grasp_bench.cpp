// Grasp generation on the fixture parts in data/parts/: time, triangles and grasps found for a
// suction cup and for parallel jaws (default GraspOptions but max_grasps 100000, seed 1). Usage: grasp_bench [repeats]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <numbers>
#include <algorithm>
#include <string>

#include "geometry/mesh_import.h"
#include "grasping/grasp_generation.h"

namespace {

using vscan::TriangleMesh;

struct FixturePart {
  const char* file;
  double metres_per_unit;
};

// Inches; centimetres at 0.127; millimetres at 0.25 (bin-sized parts).
constexpr FixturePart kParts[] = {
    {"angle_block.STL", 0.0254}, {"round.stl", 0.01 * 0.127}, {"plate_holes.STL", 0.001 * 0.25}};

TriangleMesh Load(const FixturePart& part) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/" + part.file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto mesh = vscan::geometry::ImportMesh(bytes, vscan::geometry::MeshFileFormat::kStl, part.metres_per_unit);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s: %s\n", part.file, mesh.status().ToString().c_str());
    std::exit(1);
  }
  return std::move(*mesh);
}

void Run(const char* name, const char* gripper_name, const TriangleMesh& mesh, const vscan::grasping::Gripper& gripper,
         int repeats) {
  vscan::grasping::GraspOptions options;
  options.max_grasps = 100000;  // report every grasp found
  double best_ms = 1e300;
  size_t count = 0;
  double best_quality = 0;
  double min_opening = 0, max_opening = 0;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const auto grasps = vscan::grasping::GenerateGrasps(mesh, gripper, options);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!grasps.ok()) {
      std::fprintf(stderr, "%s: %s\n", name, grasps.status().ToString().c_str());
      std::exit(1);
    }
    best_ms = std::min(best_ms, ms);
    count = grasps->size();
    best_quality = grasps->empty() ? 0 : grasps->front().quality;
    min_opening = grasps->empty() ? 0 : 1e300;
    max_opening = 0;
    for (const auto& g : *grasps) {
      min_opening = std::min(min_opening, g.opening_m);
      max_opening = std::max(max_opening, g.opening_m);
    }
  }
  std::printf("%-16s %-8s %7zu tris %9.1f ms %5zu grasps best quality %.3f openings %.1f to %.1f mm\n", name,
              gripper_name, mesh.triangles.size(), best_ms, count, best_quality, 1e3 * min_opening, 1e3 * max_opening);
}

// A UV sphere of the given radius: rings x segments x 2 triangles less the poles', for the cost of
// the brute-force ray test on a part near the ~100k-triangle limit.
TriangleMesh DenseSphere(double radius, int rings, int segments) {
  TriangleMesh m;
  for (int i = 0; i <= rings; ++i) {
    const double polar = std::numbers::pi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double az = 2 * std::numbers::pi * j / segments;
      m.vertices.emplace_back(float(radius * std::sin(polar) * std::cos(az)),
                              float(radius * std::sin(polar) * std::sin(az)), float(radius * std::cos(polar)));
    }
  }
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      const auto at = [&](int r, int s) { return uint32_t(r * segments + (s % segments)); };
      if (i > 0) m.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
      if (i + 1 < rings) m.triangles.push_back({at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
    }
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  vscan::grasping::SuctionCup cup;
  cup.diameter_m = 0.010;
  vscan::grasping::ParallelJaws jaws;
  jaws.min_opening_m = 0.002;
  jaws.max_opening_m = 0.080;
  for (const auto& part : kParts) {
    const TriangleMesh mesh = Load(part);
    Eigen::Vector3f lo, hi;
    mesh.Bounds(lo, hi);
    std::printf("%s: %.1f x %.1f x %.1f mm\n", part.file, 1e3 * (hi - lo).x(), 1e3 * (hi - lo).y(), 1e3 * (hi - lo).z());
    Run(part.file, "suction", mesh, cup, repeats);
    Run(part.file, "jaws", mesh, jaws, repeats);
  }
  const TriangleMesh sphere = DenseSphere(0.02, 160, 320);
  std::printf("sphere: 40 mm across\n");
  Run("sphere", "suction", sphere, cup, repeats);
  Run("sphere", "jaws", sphere, jaws, repeats);
  return 0;
}
