// Convex decomposition: vscan's plane cuts (physics::PlaneCutPieces, what
// PartCollision::kConvexDecomposition runs) against Bullet's HACD (hacd_pieces.h, what it ran
// before), on the fixture parts, a procedural machined riser and a torus. Per part and method:
// thread CPU seconds (median of `repeats`), pieces, how far the pieces' hulls reach from the solid
// (the worst piece, sampled every 1/200 of the part's size) and their volume over the mesh's.
//
// Usage: decomposition_bench [repeats=3] [concavity share=ConvexPieces'] [with HACD=1] [max pieces=ConvexPieces']

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/mesh_import.h"
#include "hacd_pieces.h"
#include "machined_parts.h"
#include "physics/convex_decomposition.h"
#include "physics/part_geometry.h"
#include "physics/plane_cut_decomposition.h"

namespace vscan::bench {
namespace {

using Pieces = std::vector<std::vector<Eigen::Vector3d>>;

double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

TriangleMesh LoadStl(const std::string& file, double metres_per_unit) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/" + file, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  auto mesh = geometry::ImportMesh(bytes.str(), geometry::MeshFileFormat::kStl, metres_per_unit);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s: %s\n", file.c_str(), mesh.status().ToString().c_str());
    std::exit(1);
  }
  return std::move(*mesh);
}

// A ring about z: radius 5 cm to the middle of its 2 cm tube, n x n/2 quads.
TriangleMesh Torus(int n) {
  const int m = n / 2;
  TriangleMesh mesh;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m, r = 0.05 + 0.02 * std::cos(v);
      mesh.vertices.emplace_back(float(r * std::cos(u)), float(r * std::sin(u)), float(0.02 * std::sin(v)));
    }
  }
  const auto at = [&](int a, int b) { return uint32_t((a % n) * m + b % m); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

struct Part {
  std::string name;
  TriangleMesh mesh;
};

template <class Decompose>
void Measure(const Part& part, const char* method, int repeats, Decompose decompose) {
  Eigen::Vector3f lo, hi;
  part.mesh.Bounds(lo, hi);
  const Eigen::Vector3d centre = (0.5f * (lo + hi)).cast<double>();
  const double size = static_cast<double>((hi - lo).maxCoeff());
  std::vector<double> cpu;
  Pieces pieces;
  for (int r = 0; r < repeats; ++r) {
    const double start = ThreadCpuSeconds();
    pieces = decompose(part.mesh, centre, size);
    cpu.push_back(ThreadCpuSeconds() - start);
  }
  std::sort(cpu.begin(), cpu.end());
  double reach = 0.0, volume = 0.0;
  for (const auto& piece : pieces) {
    reach = std::max(reach, physics::HullReach(part.mesh, centre, piece, size / 200));
    volume += physics::HullVolume(piece);
    if (std::getenv("VSCAN_PIECES")) std::printf("    piece %zu points volume %.3g reach %.2f mm\n", piece.size(), physics::HullVolume(piece), 1e3 * physics::HullReach(part.mesh, centre, piece, size / 200));
  }
  if (std::getenv("VSCAN_PIECES")) std::printf("    mesh volume %.4g hull %.4g\n", physics::MeshVolume(part.mesh), physics::HullVolume(physics::ExactHull(part.mesh, centre)));
  std::printf("| %s | %zu | %s | %.3f (%.3f-%.3f) | %zu | %.2f mm | %.3f |\n", part.name.c_str(),
              part.mesh.triangles.size(), method, cpu[cpu.size() / 2], cpu.front(), cpu.back(), pieces.size(),
              reach * 1e3, volume / physics::MeshVolume(part.mesh));
  std::fflush(stdout);
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  using namespace vscan;
  using namespace vscan::bench;
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const double share = argc > 2 ? std::atof(argv[2]) : physics::kDecompositionConcavityShare;
  const bool with_hacd = argc > 3 ? std::atoi(argv[3]) != 0 : true;
  const size_t max_pieces = argc > 4 ? static_cast<size_t>(std::atoi(argv[4])) : physics::kMaxDecompositionPieces;
  const std::vector<Part> parts = {
      {"angle block", LoadStl("angle_block.STL", 0.0254)},
      {"pin (tube)", LoadStl("round.stl", 0.0013)},
      {"riser", physics::test::Riser()},
      {"torus", Torus(40)},
  };
  std::printf("| part | triangles | method | CPU s median (min-max) | pieces | worst reach | volume / mesh |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const Part& part : parts) {
    Measure(part, "hull", 1, [](const TriangleMesh& mesh, const Eigen::Vector3d& centre, double) {
      return Pieces{physics::ExactHull(mesh, centre)};
    });
    Measure(part, "plane cuts", repeats, [&](const TriangleMesh& mesh, const Eigen::Vector3d& centre, double size) {
      physics::PlaneCutOptions options;  // as ConvexPieces
      options.concavity_m = share * size;
      options.max_pieces = max_pieces;
      return physics::PlaneCutPieces(mesh, centre, options);
    });
    if (with_hacd) Measure(part, "HACD", repeats, [](const TriangleMesh& mesh, const Eigen::Vector3d& centre, double) {
      return HacdPieces(mesh, centre);
    });
  }
}
