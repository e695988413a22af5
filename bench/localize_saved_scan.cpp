// The localizer in one process on a saved filled-bin scan, for profiling and for looking at what
// it misses: reads SCAN.ply (x y z nx ny nz, world frame) and SCAN.txt (first line the sensor's
// position, then one true instance per line: part index, visible fraction, 16 values of
// world_from_part row by row), localizes the three fixture parts at the bin bench's scales (angle
// block 1, tube 0.127 with 6 at most, plate 0.25 with 3) and prints, per true instance, the nearest
// estimate and whether ADD(-S) matched it.
//
//     VSCAN_PY_STUBS=build/release/python /usr/bin/python3 bench/bin_localization.py --server ADDRESS
//         --save-scans scans --peers none
//     build/release/bench/localize_saved_scan scans/1-clean [runs [parts [min_score [max_seen_through_share]]]]
//
// parts: the part indices to look for, e.g. 02 (default 012).

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "localization/baseline_localizer.h"
#include "localization/bop_scoring.h"
#include "parts_scene.h"
#include "vscan/common/cloud_io.h"

using namespace vscan;
using namespace vscan::localization;

namespace {

std::shared_ptr<TriangleMesh> Scaled(testing::FixturePart part, double scale) {
  auto mesh = std::make_shared<TriangleMesh>(*testing::LoadPart(part));
  for (auto& v : mesh->vertices) v *= static_cast<float>(scale);
  return mesh;
}

PartSymmetries Symmetries(size_t part, double scale) {
  PartSymmetries s;
  if (part == 1) {
    s = testing::SymmetriesOf(testing::FixturePart::kRound);
    for (Pose3& flip : s.discrete) flip.translation() *= scale;
  } else if (part == 2) {
    const Eigen::Vector3d centre = Eigen::Vector3d(0.2032, 0.3048, 0.0127) * scale / 2;
    for (const Eigen::Vector3d& d : {Eigen::Vector3d(-1, -1, 1), Eigen::Vector3d(1, -1, -1), Eigen::Vector3d(-1, 1, -1)}) {
      Pose3 turn = Pose3::Identity();
      turn.linear() = d.asDiagonal();
      turn.translation() = centre - turn.linear() * centre;
      s.discrete.push_back(turn);
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCAN [runs]\n", argv[0]);
    return 2;
  }
  const std::string base = argv[1];
  const int runs = argc > 2 ? std::stoi(argv[2]) : 1;
  auto scan = ReadPly(base + ".ply");
  if (!scan.ok()) {
    std::fprintf(stderr, "%s\n", scan.status().ToString().c_str());
    return 1;
  }
  std::ifstream truth_file(base + ".txt");
  Eigen::Vector3d sensor;
  truth_file >> sensor.x() >> sensor.y() >> sensor.z();
  std::vector<TrueInstance> truth;
  size_t part;
  double visible;
  while (truth_file >> part >> visible) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) truth_file >> m(r, c);
    }
    truth.push_back({static_cast<uint32_t>(part), Pose3(m), visible});
  }
  const double scales[] = {1, 0.127, 0.25};
  const size_t counts[] = {6, 6, 3};
  const std::vector<std::shared_ptr<TriangleMesh>> meshes = {Scaled(testing::FixturePart::kAngleBlock, 1),
                                                             Scaled(testing::FixturePart::kRound, 0.127),
                                                             Scaled(testing::FixturePart::kPlateHoles, 0.25)};
  std::vector<PartQuery> queries;
  std::vector<PartDefinition> definitions;
  const std::string only = argc > 3 ? argv[3] : "012";
  for (size_t p = 0; p < 3; ++p) {
    if (only.find(static_cast<char>('0' + p)) == std::string::npos) continue;
    queries.push_back({meshes[p].get(), counts[p]});
  }
  for (size_t p = 0; p < 3; ++p) {
    definitions.push_back({static_cast<uint32_t>(p), meshes[p]->vertices, Symmetries(p, scales[p])});
  }
  LocalizerOptions options;
  options.sensor_position = sensor;
  if (argc > 4) options.min_score = std::stod(argv[4]);
  if (argc > 5) options.max_seen_through_share = std::stod(argv[5]);
  StatusOr<LocalizationResult> found = Internal("not run");
  for (int run = 0; run < runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    found = LocalizeParts(queries, scan->positions, scan->normals, options);
    std::printf("localize %.0f ms\n",
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  if (!found.ok()) {
    std::fprintf(stderr, "%s\n", found.status().ToString().c_str());
    return 1;
  }
  for (size_t p = 0; p < found->parts.size(); ++p) {
    std::printf("part %zu: %zu found, %s\n", p, found->parts[p].found, found->parts[p].stop_reason.c_str());
  }
  std::vector<EstimatedInstance> estimates;
  for (const auto& i : found->instances) {
    estimates.push_back({queries.size() == 3 ? static_cast<uint32_t>(i.part) : static_cast<uint32_t>(only[i.part] - '0'),
                         i.world_from_part, i.score});
  }
  for (size_t e = 0; e < estimates.size(); ++e) {
    const Eigen::Vector3d at = estimates[e].world_from_part.translation() * 1000;
    std::printf("estimate %zu: part %u at (%.0f %.0f %.0f) score %.3f explained %zu\n", e, estimates[e].part_id, at.x(),
                at.y(), at.z(), estimates[e].score, found->instances[e].explained_points);
  }
  auto score = ScoreScan(definitions, truth, estimates);
  if (!score.ok()) {
    std::fprintf(stderr, "%s\n", score.status().ToString().c_str());
    return 1;
  }
  for (const PartScore& ps : score->parts) {
    std::printf("part %u: ADD(-S) %zu / %zu\n", ps.part_id, ps.add_correct, ps.valid_instances);
    for (const auto& m : ps.instances) {
      const TrueInstance& t = truth[m.true_index];
      double nearest = 1e9, angle = 0, est_score = 0;
      for (const auto& i : found->instances) {
        if ((queries.size() == 3 ? i.part : static_cast<size_t>(only[i.part] - '0')) != ps.part_id) continue;
        const double d = (i.world_from_part.translation() - t.world_from_part.translation()).norm();
        if (d < nearest) {
          nearest = d, est_score = i.score;
          angle = Eigen::AngleAxisd(i.world_from_part.linear().transpose() * t.world_from_part.linear()).angle() * 180 / M_PI;
        }
      }
      const Eigen::Vector3d at = t.world_from_part.translation() * 1000;
      std::printf("  truth %zu at (%.0f %.0f %.0f) mm vis %.2f %s; nearest estimate %.1f mm %.0f deg score %.2f\n",
                  m.true_index, at.x(), at.y(), at.z(), t.visible_fraction, m.estimate_index ? "OK  " : "MISS",
                  nearest * 1000, angle, est_score);
    }
  }
  return 0;
}
