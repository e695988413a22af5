// Next best views on the bunny split to four times its triangles (65k): 200k ground-truth samples,
// 100 candidates on a sphere around it at 1280x1024, thinned to the default ray budget. Prints the
// median time of PickNextBestViews with none and with half of the samples covered, and the time of
// the coverage picture; `next_best_views_bench out.png` also writes the picture.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "bench_meshes.h"
#include "evaluation/coverage_image.h"
#include "evaluation/next_best_views.h"
#include "evaluation/surface_sampling.h"

namespace vscan::bench {
namespace {

constexpr size_t kSamples = 200'000;
constexpr size_t kCandidates = 100;
constexpr double kDistance = 0.5;
constexpr int kRuns = 3;

// Each triangle split into four at its edge midpoints: the same surface with four times the triangles.
TriangleMesh SplitInFour(const TriangleMesh& mesh) {
  TriangleMesh out;
  out.vertices = mesh.vertices;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
  const auto midpoint = [&](uint32_t a, uint32_t b) {
    const auto key = std::minmax(a, b);
    const auto next = static_cast<uint32_t>(out.vertices.size());
    const auto [it, inserted] = midpoints.try_emplace({key.first, key.second}, next);
    if (inserted) out.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]) / 2);
    return it->second;
  };
  for (const auto& t : mesh.triangles) {
    const uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    out.triangles.push_back({t[0], ab, ca});
    out.triangles.push_back({ab, t[1], bc});
    out.triangles.push_back({ca, bc, t[2]});
    out.triangles.push_back({ab, bc, ca});
  }
  return out;
}

// Candidates spread evenly over a sphere around centre (a Fibonacci lattice), looking at it.
std::vector<evaluation::CandidateView> SphereOfViews(const Eigen::Vector3d& centre) {
  std::vector<evaluation::CandidateView> views;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (size_t i = 0; i < kCandidates; ++i) {
    const double y = 1 - 2 * (i + 0.5) / kCandidates;
    const double r = std::sqrt(1 - y * y);
    const Eigen::Vector3d direction(r * std::cos(golden * i), y, r * std::sin(golden * i));
    const Eigen::Vector3d up = std::abs(y) > 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    auto pose = PoseFromLookAt(centre + kDistance * direction, centre, up, "candidate");
    if (pose.ok()) views.push_back({*pose, static_cast<uint32_t>(i)});
  }
  return views;
}

// Median wall and process CPU milliseconds (all threads) of kRuns runs.
struct Timing {
  double wall_ms = 0;
  double cpu_ms = 0;
};

Timing Median(const std::function<void()>& run) {
  std::vector<double> wall, cpu;
  for (int i = 0; i < kRuns; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    run();
    cpu.push_back(1000.0 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::nth_element(wall.begin(), wall.begin() + kRuns / 2, wall.end());
  std::nth_element(cpu.begin(), cpu.begin() + kRuns / 2, cpu.end());
  return {wall[kRuns / 2], cpu[kRuns / 2]};
}

int Main(const char* png_path) {
  const TriangleMesh mesh =
      SplitInFour(ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply"));
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  const Eigen::Vector3f centre = (lo + hi) / 2;
  const std::vector<Eigen::Vector3f> samples = evaluation::SampleSurface(mesh, kSamples, 1);
  const std::vector<evaluation::CandidateView> views = SphereOfViews(centre.cast<double>());
  const sensor::PinholeCamera camera = sensor::CameraFromFov(1280, 1024, 50, 0.1, 2.0);
  const evaluation::NextBestViewOptions options;
  std::printf("bunny split in four: %zu triangles, %zu samples, %zu candidates at %ux%u, tau %.1f mm, "
              "at most %zu rays per view\n",
              mesh.triangles.size(), samples.size(), views.size(), camera.width, camera.height, options.tau * 1e3,
              options.max_rays_per_view);

  std::vector<uint8_t> none(samples.size(), 0), half(samples.size(), 0);
  for (size_t i = 0; i < samples.size(); ++i) half[i] = samples[i].x() > centre.x() ? 1 : 0;
  for (const auto& [name, covered] : {std::pair{"none covered", &none}, std::pair{"half covered", &half}}) {
    StatusOr<std::vector<evaluation::ViewPick>> picks = std::vector<evaluation::ViewPick>{};
    const Timing t =
        Median([&] { picks = evaluation::PickNextBestViews(mesh, samples, *covered, camera, views, options); });
    if (!picks.ok()) {
      std::fprintf(stderr, "bench: %s\n", picks.status().ToString().c_str());
      return 1;
    }
    std::printf("%-13s %6.0f ms wall %6.0f ms CPU  picks:", name, t.wall_ms, t.cpu_ms);
    for (const auto& pick : *picks) {
      std::printf("  #%zu +%zu -> %.3f", pick.candidate, pick.gained_samples, pick.coverage_after);
    }
    std::printf("\n");
  }

  evaluation::CoverageImageOptions picture;
  picture.up = Eigen::Vector3f::UnitY();
  StatusOr<std::string> png = std::string();
  const Timing png_time = Median([&] { png = evaluation::RenderCoveragePng(samples, half, picture); });
  if (!png.ok()) {
    std::fprintf(stderr, "bench: %s\n", png.status().ToString().c_str());
    return 1;
  }
  std::printf("coverage picture (%d px panels): %.0f ms wall %.0f ms CPU, %zu bytes\n", picture.panel_size,
              png_time.wall_ms, png_time.cpu_ms, png->size());
  if (png_path != nullptr) std::ofstream(png_path, std::ios::binary) << *png;
  return 0;
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) { return vscan::bench::Main(argc > 1 ? argv[1] : nullptr); }
