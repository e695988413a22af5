// The bunny (about 15 cm) scanned from 16 known viewpoints (12 around, 4 above), then rebuilt three
// ways: vscan's TSDF fusion and marching cubes from the range images, and PCL's and Open3D's Poisson
// (depth 8) on the same voxel-evened union with the same outward normals. Each method runs --runs
// times, round robin, so drift on this shared machine touches all alike; every mesh is then scored
// against the bunny's mesh (precision, recall, F-score, Chamfer) at two thresholds.
//
// reconstruction_bench [--runs N] [--depth D] [--tsdf-voxel MM] [--truncation VOXELS] [--union-voxel MM]
//                      [--peers 0|1]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "bench_meshes.h"
#include "evaluation/ground_truth.h"
#include "raycast/scanner.h"
#include "reconstruction/distance_trim.h"
#include "reconstruction/oriented_normals.h"
#include "reconstruction/poisson_pcl.h"
#include "reconstruction/range_image.h"
#include "reconstruction/tsdf_fusion.h"
#include "reconstruction/union_cloud.h"
#include "reconstruction_open3d.h"

namespace vscan::bench {
namespace {

using Clock = std::chrono::steady_clock;

struct Args {
  int runs = 3;
  int depth = 8;
  double tsdf_voxel_mm = 0.5;
  double union_voxel_mm = 0.8;
  double truncation_voxels = 4;
  bool peers = true;
};

Args ParseArgs(int argc, char** argv) {
  Args a;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const double value = std::atof(argv[i + 1]);
    if (flag == "--runs") a.runs = std::max(1, static_cast<int>(value));
    else if (flag == "--depth") a.depth = static_cast<int>(value);
    else if (flag == "--tsdf-voxel") a.tsdf_voxel_mm = value;
    else if (flag == "--union-voxel") a.union_voxel_mm = value;
    else if (flag == "--truncation") a.truncation_voxels = value;
    else if (flag == "--peers") a.peers = value != 0;
    else {
      std::fprintf(stderr, "reconstruction_bench: unknown flag %s\n", flag.c_str());
      std::exit(2);
    }
  }
  return a;
}

template <typename T>
T OrDie(StatusOr<T> v, const char* what) {
  if (!v.ok()) {
    std::fprintf(stderr, "reconstruction_bench: %s: %s\n", what, v.status().ToString().c_str());
    std::exit(1);
  }
  return std::move(v).value();
}

struct Scanned {
  std::vector<reconstruction::RangeImage> images;
  std::vector<PointCloud> clouds;
  std::vector<Eigen::Vector3f> origins;
  size_t points = 0;
};

// 12 views around the bunny 15 degrees above its middle, 4 more 60 degrees above, 0.45 m away,
// 640 x 480 over 40 degrees: about 0.5 mm between pixels on the bunny.
Scanned ScanBunny(const raycast::RaycastScene& scene, const Eigen::Vector3d& centre) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(640, 480, 40.0, 0.05, 2.0);
  std::vector<Eigen::Vector3d> eyes;
  const auto at = [&](double azimuth_deg, double elevation_deg) {
    const double az = azimuth_deg * std::numbers::pi / 180, el = elevation_deg * std::numbers::pi / 180;
    eyes.push_back(centre + 0.45 * Eigen::Vector3d(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az)));
  };
  for (int i = 0; i < 12; ++i) at(30.0 * i, 15.0);
  for (int i = 0; i < 4; ++i) at(45.0 + 90.0 * i, 60.0);
  Scanned s;
  for (const Eigen::Vector3d& eye : eyes) {
    const Pose3 pose = OrDie(PoseFromLookAt(eye, centre, Eigen::Vector3d::UnitY(), "bench"), "pose");
    raycast::ScanOptions options;
    options.fields = kFieldPosition | kFieldPixel;
    PointCloud cloud = OrDie(raycast::Scan(scene, camera, pose, options), "scan");
    s.images.push_back(OrDie(reconstruction::RangeImageFromScan(cloud, camera, pose), "range image"));
    s.points += cloud.size();
    s.origins.push_back(eye.cast<float>());
    s.clouds.push_back(std::move(cloud));
  }
  return s;
}

struct Timing {
  std::vector<double> seconds;
  double Median() const {
    std::vector<double> s = seconds;
    std::sort(s.begin(), s.end());
    return s.size() % 2 ? s[s.size() / 2] : 0.5 * (s[s.size() / 2 - 1] + s[s.size() / 2]);
  }
  double Min() const { return *std::min_element(seconds.begin(), seconds.end()); }
  double Max() const { return *std::max_element(seconds.begin(), seconds.end()); }
};

TriangleMesh Timed(Timing& t, const std::function<TriangleMesh()>& run) {
  const auto t0 = Clock::now();
  TriangleMesh mesh = run();
  t.seconds.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  return mesh;
}

struct Method {
  std::string name;
  std::function<TriangleMesh()> run;
  Timing timing;
  TriangleMesh mesh;
};

void PrintScores(const char* name, const std::vector<evaluation::Evaluation>& scores) {
  std::printf("| %s |", name);
  for (const auto& e : scores) {
    std::printf(" %.3f | %.3f | %.3f |", e.precision, e.recall, e.f_score);
  }
  std::printf(" %.3f | %.3f | %.3f |\n", scores[0].accuracy.mean * 1e3, scores[0].completeness.mean * 1e3,
              scores[0].chamfer * 1e3);
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  using namespace vscan;
  using namespace vscan::bench;
  const Args args = ParseArgs(argc, argv);

  const TriangleMesh bunny = ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply");
  Eigen::Vector3f lo, hi;
  bunny.Bounds(lo, hi);
  raycast::SceneInstance instance;
  instance.mesh = std::make_shared<const TriangleMesh>(bunny);
  const auto scene = OrDie(raycast::RaycastScene::Build(std::span<const raycast::SceneInstance>(&instance, 1)), "scene");
  const Scanned scanned = ScanBunny(*scene, (0.5f * (lo + hi)).cast<double>());

  // The union, evened out, with normals facing the sensors: the Poisson peers' shared input.
  std::vector<reconstruction::ScanPoints> scans;
  for (size_t i = 0; i < scanned.clouds.size(); ++i) scans.push_back({scanned.clouds[i].positions, scanned.origins[i]});
  const float union_voxel = static_cast<float>(args.union_voxel_mm * 1e-3);
  auto t0 = Clock::now();
  const reconstruction::UnionCloud cloud = reconstruction::VoxelDownsample(scans, union_voxel);
  const double downsample_s = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  const reconstruction::OrientedCloud oriented =
      OrDie(reconstruction::OrientNormals(cloud.positions, cloud.view_directions, 16), "normals");
  const double normals_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const float trim_distance = 2 * union_voxel;

  reconstruction::TsdfFusionOptions tsdf;
  tsdf.tsdf.voxel_size = static_cast<float>(args.tsdf_voxel_mm * 1e-3);
  tsdf.tsdf.truncation_voxels = static_cast<float>(args.truncation_voxels);
  tsdf.min_component_triangles = 100;
  reconstruction::PoissonOptions poisson;
  poisson.depth = args.depth;

  std::vector<Method> methods;
  reconstruction::TsdfFusionStats tsdf_stats;
  methods.push_back({"vscan TSDF + marching cubes", [&] {
                       return OrDie(reconstruction::FuseRangeImages(scanned.images, tsdf, &tsdf_stats), "tsdf");
                     }});
  if (args.peers) {
    methods.push_back({"PCL Poisson", [&] {
                         return OrDie(reconstruction::PoissonPcl(oriented.positions, oriented.normals, poisson), "pcl");
                       }});
  }
  if (args.peers && Open3dAvailable()) {
    methods.push_back({"Open3D Poisson", [&] { return Open3dPoisson(oriented.positions, oriented.normals, args.depth); }});
  }
  for (int r = 0; r < args.runs; ++r) {
    for (Method& m : methods) m.mesh = Timed(m.timing, m.run);
  }
  // The Poisson surfaces are closed: trim both where nothing was seen, by the same rule.
  for (size_t i = 1; i < methods.size(); ++i) reconstruction::TrimFarFromPoints(methods[i].mesh, oriented.positions, trim_distance);

  const double poisson_best = [&] {
    double best = methods.size() > 1 ? 1e300 : 1.0;
    for (size_t i = 1; i < methods.size(); ++i) best = std::min(best, methods[i].timing.Median());
    return best;
  }();
  std::printf("\nbunny %.0f x %.0f x %.0f mm, %zu views of 640 x 480, %zu points scanned; union evened at %.2f mm: %zu "
              "points with normals (evening %.2f s, normals %.2f s); TSDF voxel %.2f mm, truncation %.1f voxels; "
              "Poisson depth %d, trimmed %.1f mm from the union; %d runs\n\n",
              (hi - lo).x() * 1e3, (hi - lo).y() * 1e3, (hi - lo).z() * 1e3, scanned.images.size(), scanned.points,
              args.union_voxel_mm, oriented.positions.size(), downsample_s, normals_s, args.tsdf_voxel_mm,
              args.truncation_voxels, args.depth,
              trim_distance * 1e3, args.runs);
  std::printf("| method | median s | min s | max s | / faster Poisson | triangles |\n|---|---|---|---|---|---|\n");
  for (const Method& m : methods) {
    std::printf("| %s | %.3f | %.3f | %.3f | %.3f | %zu |\n", m.name.c_str(), m.timing.Median(), m.timing.Min(),
                m.timing.Max(), m.timing.Median() / poisson_best, m.mesh.triangles.size());
  }

  std::printf("\nTSDF, last run: %zu blocks (%.0f MB of voxels), integration %.0f ms, marching cubes %.0f ms, "
              "clean-up %.0f ms\n",
              tsdf_stats.blocks,
              tsdf_stats.blocks * reconstruction::VoxelBlocks::kVoxels * sizeof(reconstruction::TsdfVoxel) / 1e6,
              tsdf_stats.integrate_ms, tsdf_stats.extract_ms, tsdf_stats.cleanup_ms);

  const std::vector<double> taus = {0.001, 0.002};
  std::vector<evaluation::GroundTruth> truths;
  for (double tau : taus) {
    evaluation::EvaluationOptions options;
    options.tau = tau;
    truths.push_back(OrDie(evaluation::GroundTruth::Prepare(bunny, options), "ground truth"));
  }
  std::printf("\n| reconstruction | P 1 mm | R 1 mm | F 1 mm | P 2 mm | R 2 mm | F 2 mm | accuracy mm | completeness mm "
              "| Chamfer mm |\n|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<evaluation::Evaluation> scores;
  for (const auto& truth : truths) scores.push_back(truth.EvaluatePoints(oriented.positions));
  PrintScores("union (coverage = R)", scores);
  for (const Method& m : methods) {
    scores.clear();
    for (const auto& truth : truths) scores.push_back(OrDie(truth.EvaluateMesh(m.mesh), "evaluation"));
    PrintScores(m.name.c_str(), scores);
  }
  if (!Open3dAvailable()) std::printf("\nOpen3D was not found at configure time: its peer was skipped.\n");
  return 0;
}
