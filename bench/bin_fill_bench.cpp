// Fills a 30 x 20 x 15 cm bin with 50 fixture parts (angle blocks and pins) with FillBin and with
// a plain PyBullet-like Bullet world under the same spawn and settle rules, over several seeds;
// then scans each settled bin of ours at 1280 x 1024.
// Each fill of hulls is also run by the fill as it was before the meshes' overlaps were bounded
// (FillOld), seed by seed in the same run, for the ratio of their CPU times.
// Then (sections "machined" and "decomposition") fills bins of procedural machined parts (risers and
// many-sided prisms, hulls of 100-300 vertices) and of the fixture parts, each as convex hulls and
// as convex decompositions, and reports how deep the settled meshes overlap.
// Sections "fixture-pile" (the fixture section's 50 parts, the dataset plan's mix) and "machined-pile" (25 risers,
// 25 prisms) fill 50 parts as hulls beside the old fill only.
// Usage: bin_fill_bench [seeds=3] [sections=fixture,machined,decomposition(,fixture-pile,machined-pile)(,hull-only)]
//        [max simulated s=60]
//        [hull tolerance mm=FillOptions' default]

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bin_fill_plain_world.h"
#include "machined_parts.h"
#include "geometry/mesh_import.h"
#include "physics/bin_fill.h"
#include "physics/bullet_fill_world.h"
#include "physics/convex_decomposition.h"
#include "physics/fill_loop.h"
#include "physics/mesh_overlap.h"
#include "physics/part_geometry.h"
#include "raycast/raycast_scene.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"

namespace vscan::bench {
namespace {

using Clock = std::chrono::steady_clock;

double g_hull_tolerance_m = -1;  // < 0: FillOptions' default

double Since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// CPU seconds of this thread: a fill runs on one thread, and other loads on the machine stretch
// its wall time but not this.
double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

physics::PartType LoadPart(const std::string& file, double metres_per_unit, const std::string& name, size_t count) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/" + file, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  auto mesh = geometry::ImportMesh(bytes.str(), geometry::MeshFileFormat::kStl, metres_per_unit);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s: %s\n", file.c_str(), mesh.status().ToString().c_str());
    std::exit(1);
  }
  physics::PartType part;
  part.name = name;
  part.mesh = std::move(*mesh);
  part.count = count;
  return part;
}

struct Run {
  physics::FillResult fill;
  double wall_s = 0.0;
  double cpu_s = 0.0;
};

Run FillOurs(const physics::BinSpec& bin, const std::vector<physics::PartType>& parts,
             const physics::FillOptions& options) {
  const auto start = Clock::now();
  const double cpu_start = ThreadCpuSeconds();
  auto result = physics::FillBin(bin, parts, options);
  if (!result.ok()) {
    std::fprintf(stderr, "FillBin: %s\n", result.status().ToString().c_str());
    std::exit(1);
  }
  return {std::move(*result), Since(start), ThreadCpuSeconds() - cpu_start};
}

Run FillPlain(const physics::BinSpec& bin, const std::vector<physics::PartType>& parts,
              const physics::FillOptions& options) {
  const auto start = Clock::now();
  const double cpu_start = ThreadCpuSeconds();
  std::vector<physics::PartGeometry> geometry;
  for (const auto& part : parts) {
    geometry.push_back(physics::MakePartGeometry(part, 0.0));
  }
  auto world = MakePlainFillWorld(bin, parts, geometry, options);
  Run run{physics::RunFill(bin, parts, geometry, options, *world, nullptr), 0.0, 0.0};
  run.wall_s = Since(start);
  run.cpu_s = ThreadCpuSeconds() - cpu_start;
  return run;
}

// The fill as it was before the true-mesh overlaps were bounded: each hull cut to the 24 of its
// vertices farthest apart, GJK's contact normals and a bin without faces (no separating-axis
// test), no overlap measure and no separation; the same world and loop
// otherwise. Timed like FillOurs; the meshes' overlaps are measured afterwards, untimed, for the
// report.
Run FillOld(const physics::BinSpec& bin, const std::vector<physics::PartType>& parts, physics::FillOptions options) {
  const auto start = Clock::now();
  const double cpu_start = ThreadCpuSeconds();
  std::vector<physics::PartGeometry> geometry = physics::MakePartGeometries(parts, 0.0);
  for (auto& part : geometry) {
    part.hull = physics::FarthestPoints(part.hull, 24);
    part.radius = 0.0;
    for (const auto& p : part.hull) part.radius = std::max(part.radius, p.norm());
  }
  options.measure_mesh_overlaps = false;
  options.separating_axis_contacts = false;
  auto world = physics::MakeBulletFillWorld(bin, geometry, options);
  Run run{physics::RunFill(bin, parts, geometry, options, *world, nullptr), 0.0, 0.0};
  run.wall_s = Since(start);
  run.cpu_s = ThreadCpuSeconds() - cpu_start;
  run.fill.mesh_overlap = physics::MeasureMeshOverlaps(bin, parts, run.fill.parts);
  return run;
}

TriangleMesh Box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back(Eigen::Vector3d((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                                               (i & 4) ? hi.z() : lo.z())
                                   .cast<float>());
  }
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

// The bin's floor and walls as meshes in the bin frame.
std::vector<std::shared_ptr<const TriangleMesh>> BinMeshes(const physics::BinSpec& bin) {
  const Eigen::Vector3d s = bin.inner_size;
  const double w = bin.wall_thickness;
  const Eigen::Vector3d outer(0.5 * s.x() + w, 0.5 * s.y() + w, s.z());
  return {
      std::make_shared<const TriangleMesh>(Box({-outer.x(), -outer.y(), -w}, {outer.x(), outer.y(), 0})),
      std::make_shared<const TriangleMesh>(Box({0.5 * s.x(), -outer.y(), 0}, outer)),
      std::make_shared<const TriangleMesh>(Box({-outer.x(), -outer.y(), 0}, {-0.5 * s.x(), outer.y(), s.z()})),
      std::make_shared<const TriangleMesh>(Box({-0.5 * s.x(), 0.5 * s.y(), 0}, {0.5 * s.x(), outer.y(), s.z()})),
      std::make_shared<const TriangleMesh>(Box({-0.5 * s.x(), -outer.y(), 0}, {0.5 * s.x(), -0.5 * s.y(), s.z()})),
  };
}

struct ScanTiming {
  double wall_s = 0.0;
  size_t points = 0;
};

// Builds the Embree scene of the settled bin and casts one 1280 x 1024 scan from above it.
ScanTiming ScanBin(const physics::BinSpec& bin, const std::vector<std::shared_ptr<const TriangleMesh>>& part_meshes,
                   const physics::FillResult& fill) {
  const auto start = Clock::now();
  std::vector<raycast::SceneInstance> instances;
  uint32_t id = 1;
  for (const auto& wall : BinMeshes(bin)) instances.push_back({wall, bin.world_from_bin, 1.0, id++});
  for (const physics::PlacedPart& part : fill.parts) {
    instances.push_back({part_meshes[part.type], part.world_from_part, 1.0, id++});
  }
  auto scene = raycast::RaycastScene::Build(instances);
  if (!scene.ok()) {
    std::fprintf(stderr, "scene: %s\n", scene.status().ToString().c_str());
    std::exit(1);
  }
  const sensor::PinholeCamera camera = sensor::CameraFromFov(1280, 1024, 50, 0.05, 3.0);
  const Eigen::Vector3d centre = bin.world_from_bin * Eigen::Vector3d(0, 0, 0.5 * bin.inner_size.z());
  const Pose3 sensor_pose =
      *PoseFromLookAt(centre + Eigen::Vector3d(0, 0, 0.55), centre, Eigen::Vector3d::UnitY(), "sensor");
  auto cloud = raycast::Scan(**scene, camera, sensor_pose, raycast::ScanOptions{});
  if (!cloud.ok()) {
    std::fprintf(stderr, "scan: %s\n", cloud.status().ToString().c_str());
    std::exit(1);
  }
  return {Since(start), cloud->size()};
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Summary {
  std::vector<double> per_minute, per_cpu_minute, simulated_s, steps, wall_s;
  double max_penetration_m = 0.0, max_mesh_overlap_m = 0.0;
  size_t outside = 0, placed = 0;
  std::map<std::string, int> ends;

  void Add(const Run& run) {
    per_minute.push_back(60.0 / run.wall_s);
    per_cpu_minute.push_back(60.0 / run.cpu_s);
    wall_s.push_back(run.wall_s);
    simulated_s.push_back(run.fill.simulated_s);
    steps.push_back(static_cast<double>(run.fill.steps));
    max_penetration_m = std::max(
        {max_penetration_m, run.fill.max_part_part_penetration_m, run.fill.max_part_bin_penetration_m});
    max_mesh_overlap_m = std::max(
        {max_mesh_overlap_m, run.fill.mesh_overlap.max_part_part_m, run.fill.mesh_overlap.max_part_bin_m});
    outside += run.fill.outside.size();
    placed += run.fill.parts.size();
    ++ends[physics::FillEndName(run.fill.end)];
  }

  void Print(const char* name) const {
    std::string ends_text;
    for (const auto& [end, count] : ends) ends_text += end + "=" + std::to_string(count) + " ";
    std::printf("%-6s fills/min median %6.1f min %6.1f max %6.1f | per CPU minute median %6.1f | sim s median %5.2f | steps median %6.0f | "
                "max penetration %.2f mm, mesh overlap %.3f mm | parts in bins %zu, outside %zu | %s\n",
                name, Median(per_minute), *std::min_element(per_minute.begin(), per_minute.end()),
                *std::max_element(per_minute.begin(), per_minute.end()), Median(per_cpu_minute), Median(simulated_s), Median(steps),
                max_penetration_m * 1e3, max_mesh_overlap_m * 1e3, placed, outside, ends_text.c_str());
  }
};

// Bins per wall-clock minute with one fill per core at a time: a fill steps one Bullet world on
// one thread, so a machine fills as many bins at once as it has cores (the dataset job does too).
template <typename FillAndScan>
double BinsPerMinuteOnAllCores(unsigned workers, int bins, FillAndScan fill_and_scan) {
  std::atomic<int> next{1};
  const auto start = Clock::now();
  std::vector<std::thread> threads;
  for (unsigned w = 0; w < workers; ++w) {
    threads.emplace_back([&] {
      for (int seed = next++; seed <= bins; seed = next++) fill_and_scan(seed);
    });
  }
  for (auto& thread : threads) thread.join();
  return 60.0 * bins / Since(start);
}

physics::PartType Procedural(TriangleMesh mesh, const std::string& name, size_t count) {
  physics::PartType part;
  part.name = name;
  part.mesh = std::move(mesh);
  part.count = count;
  return part;
}

void PrintFill(const std::string& name, int seed, const Run& run) {
  const physics::MeshOverlaps& overlap = run.fill.mesh_overlap;
  std::printf("  %-6s seed %d  %.3f s (CPU %.3f, set-up %.3f, overlap measure %.3f) %s sim %.2f s, %zu in, "
              "%zu out | shapes %.3f/%.3f mm | meshes part-part max %.3f p95 %.3f (%zu pairs) part-bin %.3f mm | "
              "moved %zu, %d rounds\n",
              name.c_str(), seed, run.wall_s, run.cpu_s, run.fill.setup_wall_s, run.fill.measure_wall_s,
              physics::FillEndName(run.fill.end), run.fill.simulated_s, run.fill.parts.size(), run.fill.outside.size(),
              run.fill.max_part_part_penetration_m * 1e3, run.fill.max_part_bin_penetration_m * 1e3,
              overlap.max_part_part_m * 1e3, overlap.p95_part_part_m * 1e3, overlap.overlapping_pairs,
              overlap.max_part_bin_m * 1e3, overlap.moved_parts, overlap.rounds);
  std::fflush(stdout);
}

std::string Spread(const std::vector<double>& v) {
  char text[96];
  std::snprintf(text, sizeof text, "median %.3f (min %.3f max %.3f)", Median(v), *std::min_element(v.begin(), v.end()),
                *std::max_element(v.begin(), v.end()));
  return text;
}

// The same parts filled as hulls (each seed also by the old fill, FillOld, right after) and as
// convex decompositions, seeds 1..seeds each: one line per fill, a summary per kind and the
// ratios of their thread CPU seconds, seed by seed.
void CompareCollisions(const std::string& title, const physics::BinSpec& bin, std::vector<physics::PartType> parts,
                       int seeds, double max_simulated_s, bool hull_only) {
  std::printf("%s, %d seeds, max simulated %.0f s\n", title.c_str(), seeds, max_simulated_s);
  std::map<std::string, std::vector<double>> cpu, wall_per_sim;
  std::vector<double> new_over_old;
  for (const auto collision : {physics::PartCollision::kConvexHull, physics::PartCollision::kConvexDecomposition}) {
    if (hull_only && collision != physics::PartCollision::kConvexHull) break;
    const bool hull = collision == physics::PartCollision::kConvexHull;
    const std::string name = hull ? "hull" : "decomp";
    for (auto& part : parts) part.collision = collision;
    Summary summary, old_summary;
    for (int seed = 1; seed <= seeds; ++seed) {
      physics::FillOptions options;
      options.seed = static_cast<uint64_t>(seed);
      options.max_simulated_s = max_simulated_s;
      if (g_hull_tolerance_m >= 0) options.hull_tolerance_m = g_hull_tolerance_m;
      const Run run = FillOurs(bin, parts, options);
      PrintFill(name, seed, run);
      summary.Add(run);
      cpu[name].push_back(run.cpu_s);
      wall_per_sim[name].push_back(run.wall_s / std::max(run.fill.simulated_s, 1e-9));
      if (!hull) continue;
      const Run old = FillOld(bin, parts, options);
      PrintFill("old", seed, old);
      old_summary.Add(old);
      cpu["old"].push_back(old.cpu_s);
      new_over_old.push_back(run.cpu_s / old.cpu_s);
    }
    summary.Print(name.c_str());
    std::printf("  %-6s CPU s %s, wall per simulated s median %.3f\n", name.c_str(), Spread(cpu[name]).c_str(),
                Median(wall_per_sim[name]));
    if (!hull) continue;
    old_summary.Print("old");
    std::printf("  old    CPU s %s\n", Spread(cpu["old"]).c_str());
    std::printf("  hull / old, CPU seed by seed: %s; ratio of the CPU medians %.2f\n", Spread(new_over_old).c_str(),
                Median(cpu["hull"]) / Median(cpu["old"]));
  }
  if (hull_only) return;
  std::printf("  decomp / hull, CPU: first fill (decomposition computed) %.2f, ratio of the medians %.2f, of the "
              "medians of later fills %.2f\n",
              cpu["decomp"][0] / cpu["hull"][0], Median(cpu["decomp"]) / Median(cpu["hull"]),
              seeds > 1 ? Median(std::vector<double>(cpu["decomp"].begin() + 1, cpu["decomp"].end())) /
                              Median(std::vector<double>(cpu["hull"].begin() + 1, cpu["hull"].end()))
                        : 0.0);
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  using namespace vscan;
  using namespace vscan::bench;
  const int seeds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const std::string sections = argc > 2 ? argv[2] : "fixture,machined,decomposition";
  const double max_simulated_s = argc > 3 ? std::atof(argv[3]) : 60.0;
  if (argc > 4) g_hull_tolerance_m = 1e-3 * std::atof(argv[4]);
  // As vscand keeps them in its data directory: decompositions read back by a later run.
  if (const char* dir = std::getenv("VSCAN_DECOMPOSITION_DIR")) vscan::physics::SetDecompositionDirectory(dir);
  // A section is wanted when named whole: "machined" is not "machined-pile".
  const auto wanted = [&](const std::string& section) {
    return ("," + sections + ",").find("," + section + ",") != std::string::npos;
  };
  physics::BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.30, 0.20, 0.15);
  bin.wall_thickness = 0.01;
  // angle_block is in inches; round (5.08 x 60.96 units, longer than the bin in any plain unit) is
  // scaled to a 6.6 mm x 79 mm pin; plate_holes (203 x 305 mm) does not fit the bin.
  const std::vector<physics::PartType> parts = {LoadPart("angle_block.STL", 0.0254, "angle_block", 25),
                                                LoadPart("round.stl", 0.0013, "round", 25)};
  std::vector<std::shared_ptr<const TriangleMesh>> part_meshes;
  for (const auto& part : parts) part_meshes.push_back(std::make_shared<const TriangleMesh>(part.mesh));
  if (wanted("machined")) {
    CompareCollisions("bin 30 x 20 x 15 cm, 10 risers (40 x 30 x 18 mm, bosses and pockets) + 10 96-sided prisms "
                      "(24 x 20 mm)",
                      bin, {Procedural(physics::test::Riser(), "riser", 10), Procedural(physics::test::ManySidedPrism(), "prism", 10)},
                      seeds, max_simulated_s, wanted("hull-only"));
  }
  if (wanted("decomposition")) {
    CompareCollisions("bin 30 x 20 x 15 cm, 11 angle blocks + 11 pins", bin,
                      {LoadPart("angle_block.STL", 0.0254, "angle_block", 11), LoadPart("round.stl", 0.0013, "round", 11)},
                      seeds, max_simulated_s, wanted("hull-only"));
  }
  if (wanted("machined-pile")) {
    CompareCollisions("bin 30 x 20 x 15 cm, 25 risers + 25 96-sided prisms", bin,
                      {Procedural(physics::test::Riser(), "riser", 25), Procedural(physics::test::ManySidedPrism(), "prism", 25)},
                      seeds, max_simulated_s, true);
  }
  if (wanted("fixture-pile")) {
    CompareCollisions("bin 30 x 20 x 15 cm, 25 angle blocks + 25 pins (the dataset plan's mix)", bin, parts, seeds,
                      max_simulated_s, true);
  }
  if (!wanted("fixture")) return 0;
  std::printf("bin 30 x 20 x 15 cm, 25 angle blocks (3.4 x 2.5 x 3.4 cm) + 25 pins (6.6 mm x 79 mm), %d seeds\n",
              seeds);

  Summary ours, plain, old;
  std::vector<double> with_scan, scan_s, ours_cpu, old_cpu, ours_over_old;
  for (int seed = 1; seed <= seeds; ++seed) {
    physics::FillOptions options;
    options.seed = static_cast<uint64_t>(seed);
    if (g_hull_tolerance_m >= 0) options.hull_tolerance_m = g_hull_tolerance_m;
    const Run our_run = FillOurs(bin, parts, options);
    const ScanTiming scan = ScanBin(bin, part_meshes, our_run.fill);
    const Run plain_run = FillPlain(bin, parts, options);
    const Run old_run = FillOld(bin, parts, options);
    PrintFill("old", seed, old_run);
    old.Add(old_run);
    ours_cpu.push_back(our_run.cpu_s);
    old_cpu.push_back(old_run.cpu_s);
    ours_over_old.push_back(our_run.cpu_s / old_run.cpu_s);
    std::printf("seed %d  ours %.3f s (CPU %.3f s, set-up %.3f, steps %.3f, of which overlap measure %.3f) %s sim %.2f s, "
                "%zu in, %zu out, pen %.2f/%.2f mm, mesh overlap part-part max %.3f p95 %.3f (%zu pairs) part-bin %.3f mm | "
                "scan %.3f s %zu points | plain %.3f s (CPU %.3f s) %s sim %.2f s, %zu in, %zu out, pen %.2f/%.2f mm\n",
                seed, our_run.wall_s, our_run.cpu_s, our_run.fill.setup_wall_s, our_run.fill.step_wall_s,
                our_run.fill.measure_wall_s, physics::FillEndName(our_run.fill.end), our_run.fill.simulated_s,
                our_run.fill.parts.size(), our_run.fill.outside.size(), our_run.fill.max_part_part_penetration_m * 1e3,
                our_run.fill.max_part_bin_penetration_m * 1e3, our_run.fill.mesh_overlap.max_part_part_m * 1e3,
                our_run.fill.mesh_overlap.p95_part_part_m * 1e3, our_run.fill.mesh_overlap.overlapping_pairs,
                our_run.fill.mesh_overlap.max_part_bin_m * 1e3, scan.wall_s, scan.points, plain_run.wall_s, plain_run.cpu_s,
                physics::FillEndName(plain_run.fill.end), plain_run.fill.simulated_s, plain_run.fill.parts.size(),
                plain_run.fill.outside.size(), plain_run.fill.max_part_part_penetration_m * 1e3,
                plain_run.fill.max_part_bin_penetration_m * 1e3);
    std::fflush(stdout);
    ours.Add(our_run);
    plain.Add(plain_run);
    with_scan.push_back(60.0 / (our_run.wall_s + scan.wall_s));
    scan_s.push_back(scan.wall_s);
  }
  ours.Print("ours");
  plain.Print("plain");
  old.Print("old");
  std::printf("CPU s per fill: ours %s, old %s; ours / old seed by seed %s\n", Spread(ours_cpu).c_str(),
              Spread(old_cpu).c_str(), Spread(ours_over_old).c_str());
  std::printf("ratio of median fills per minute (ours / plain): %.2f wall, %.2f CPU\n",
              Median(ours.per_minute) / Median(plain.per_minute),
              Median(ours.per_cpu_minute) / Median(plain.per_cpu_minute));
  std::printf("fill + 1280x1024 scan, one bin at a time: bins/min median %.1f min %.1f max %.1f (scan median %.3f s)\n",
              Median(with_scan), *std::min_element(with_scan.begin(), with_scan.end()),
              *std::max_element(with_scan.begin(), with_scan.end()), Median(scan_s));

  const unsigned workers = std::max(1u, std::thread::hardware_concurrency());
  const int bins = 2 * seeds * static_cast<int>(workers);
  const double ours_all_cores = BinsPerMinuteOnAllCores(workers, bins, [&](int seed) {
    physics::FillOptions options;
    options.seed = static_cast<uint64_t>(seed);
    ScanBin(bin, part_meshes, FillOurs(bin, parts, options).fill);
  });
  const double plain_all_cores = BinsPerMinuteOnAllCores(workers, bins, [&](int seed) {
    physics::FillOptions options;
    options.seed = static_cast<uint64_t>(seed);
    ScanBin(bin, part_meshes, FillPlain(bin, parts, options).fill);
  });
  std::printf("fill + 1280x1024 scan, %u bins at once on %u cores, seeds 1-%d: ours %.1f bins/min, plain %.1f bins/min, "
              "ratio %.2f\n",
              workers, workers, bins, ours_all_cores, plain_all_cores, ours_all_cores / plain_all_cores);
  return 0;
}
