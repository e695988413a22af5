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
#include <string>
#include <vector>

#include "fixture_parts.h"
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
  }
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
      {"angle block", physics::test::AngleBlock(1).mesh},
      {"pin (tube)", physics::test::RoundPin(1).mesh},
      {"riser", physics::test::Riser()},
      {"torus", physics::test::Torus(40)},
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
