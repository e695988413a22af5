// The model.json printer of `vscan align|reconstruct|evaluate` and `vscan campaign run`: a
// hand-written report printed line by line, with its numbers converted to the units shown.

#include "model/model_report.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace vscan::cli {
namespace {

const char* const kReport = R"json({
  "job_id": "job_7", "kind": "model", "state": "SUCCEEDED",
  "frame": "model (world, table at 0 deg)",
  "scene_id": "scn_1", "clouds": 3,
  "crop": {"kind": "cylinder", "radius": 0.1},
  "alignment": {
    "initial_pose": "known", "voxel_size": 0.002, "pose_graph": true, "seconds": 1.26,
    "aligned": 2, "unaligned": 1,
    "rotation_error_deg": {"mean": 0.0124, "max": 0.031},
    "translation_error_m": {"mean": 0.00008, "max": 0.00021},
    "initial_rotation_error_deg": {"mean": 0.21, "max": 0.5},
    "initial_translation_error_m": {"mean": 0.0012, "max": 0.0025},
    "scans": [
      {"index": 0, "cloud_id": "cld_a", "name": "scan-r00-v00.ply", "aligned": true, "reason": "", "fitness": 0.93},
      {"index": 1, "cloud_id": "cld_b", "name": "scan-r01-v00.ply", "aligned": true, "reason": "", "fitness": 0.9},
      {"index": 2, "cloud_id": "cld_c", "name": "", "aligned": false, "reason": "fitness 0.12 below 0.3"}
    ],
    "artifact": "aligned.ply"
  },
  "reconstruction": {"method": "tsdf", "voxel_size": 0.001, "vertices": 12345, "triangles": 24680, "seconds": 4.06,
                     "artifact": "mesh.ply"},
  "evaluation": {
    "tau": 0.001, "ground_truth": {"objects": ["obj_1"], "area_m2": 0.05712, "samples": 100000}, "seconds": 2.14,
    "union": {"precision": 0.981, "recall": 0.934, "f_score": 0.9569, "accuracy_mean": 0.00021,
              "accuracy_median": 0.00015, "completeness_mean": 0.00045, "completeness_median": 0.0002,
              "chamfer": 0.00033},
    "mesh": {"precision": 0.99, "recall": 0.95, "f_score": 0.9696, "accuracy_mean": 0.0001,
             "accuracy_median": 0.00008, "completeness_mean": 0.0003, "completeness_median": 0.00012,
             "chamfer": 0.0002},
    "coverage": 0.934, "uncovered_artifact": "uncovered.ply", "coverage_image": "coverage.png",
    "next_best_views": [
      {"position": [0.3, 0.1, 0.2], "target": [0, 0, 0.07], "table_angle_deg": 90, "coverage_gain": 0.032,
       "coverage_after": 0.966},
      {"position": [-0.25, 0, 0.35], "target": [0, 0, 0.05], "table_angle_deg": 180, "coverage_gain": 0.011,
       "coverage_after": 0.977}
    ]
  }
})json";

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string Printed(const std::string& json) {
  const auto report = ParseModelReport(json);
  EXPECT_TRUE(report.ok()) << report.status().message();
  return report.ok() ? FormatModelReport(*report) : "";
}

TEST(ModelReport, PrintsEverySectionInItsUnits) {
  const std::vector<std::string> expected = {
      "3 clouds of scene scn_1, in the model (world, table at 0 deg); crop: cylinder",
      "alignment: 2 of 3 scans aligned (known initial poses, voxel 2.000 mm, pose graph) in 1.3 s",
      "  pose error:    rotation mean 0.012, max 0.031 deg; translation mean 0.080, max 0.210 mm",
      "  started from:  rotation mean 0.210, max 0.500 deg; translation mean 1.200, max 2.500 mm",
      "  scan 2 (cld_c) NOT aligned: fitness 0.12 below 0.3",
      "  aligned scans: aligned.ply",
      "reconstruction: tsdf, voxel 1.000 mm: 12345 vertices, 24680 triangles in 4.1 s: mesh.ply",
      "evaluation at tau 1.000 mm against 1 object (0.0571 m2, 100000 samples) in 2.1 s:",
      "  part    precision   recall  F-score      accuracy mm  completeness mm  Chamfer mm",
      "                                         mean / median    mean / median",
      "  union      98.1 %   93.4 %   95.7 %    0.210 / 0.150    0.450 / 0.200       0.330",
      "  mesh       99.0 %   95.0 %   97.0 %    0.100 / 0.080    0.300 / 0.120       0.200",
      "  coverage 93.4 % (uncovered.ply, coverage.png)",
      "next best views (world frame, table at the angle given):",
      "  1. position 0.300, 0.100, 0.200  target 0.000, 0.000, 0.070  table 90.0 deg  +3.2 % -> 96.6 %",
      "  2. position -0.250, 0.000, 0.350  target 0.000, 0.000, 0.050  table 180.0 deg  +1.1 % -> 97.7 %",
  };
  EXPECT_EQ(Lines(Printed(kReport)), expected);
}

TEST(ModelReport, LeavesOutThePartsThatDidNotRun) {
  const std::string printed = Printed(R"({"job_id": "job_8", "clouds": 2, "state": "SUCCEEDED",
      "alignment": {"initial_pose": "features", "pose_graph": false, "aligned": 2, "unaligned": 0,
                    "scans": [{"index": 0, "cloud_id": "cld_a", "aligned": true}]}})");
  EXPECT_EQ(Lines(printed), (std::vector<std::string>{
                                "2 clouds",
                                "alignment: 2 of 2 scans aligned (features initial poses, no pose graph)",
                            }));
}

TEST(ModelReport, SaysWhyThereAreNoNextBestViews) {
  const std::string printed = Printed(R"({"evaluation": {"tau": 0.002, "coverage": 0.5,
      "union": {"precision": 1, "recall": 0.5, "f_score": 0.6667, "accuracy_mean": 0, "accuracy_median": 0,
                "completeness_mean": 0.004, "completeness_median": 0.001, "chamfer": 0.002},
      "next_best_views": [], "next_best_views_note": "the scene has no robot mount"}})");
  const auto lines = Lines(printed);
  ASSERT_EQ(lines.size(), 6u) << printed;
  EXPECT_EQ(lines[0], "evaluation at tau 2.000 mm:");
  EXPECT_EQ(lines[3], "  union     100.0 %   50.0 %   66.7 %    0.000 / 0.000    4.000 / 1.000       2.000");
  EXPECT_EQ(lines[4], "  coverage 50.0 %");
  EXPECT_EQ(lines[5], "next best views: none (the scene has no robot mount)");
}

TEST(ModelReport, RefusesWhatIsNotAJsonObject) {
  EXPECT_EQ(ParseModelReport("[1, 2]").status().code(), StatusCode::kDataLoss);
  EXPECT_EQ(ParseModelReport("{\"clouds\": ").status().code(), StatusCode::kDataLoss);
}

TEST(ModelReport, JsonOnOneLineKeepsTheValues) {
  const auto report = ParseModelReport(kReport);
  ASSERT_TRUE(report.ok());
  const std::string json = ReportJson(*report);
  EXPECT_EQ(json.find('\n'), std::string::npos);
  const auto again = ParseModelReport(json);
  ASSERT_TRUE(again.ok()) << json;
  EXPECT_EQ(FormatModelReport(*again), FormatModelReport(*report));
}

TEST(ModelReport, ScanAlignmentLine) {
  v1::ScanAlignment scan;
  scan.set_index(3);
  scan.set_cloud_id("cld_x");
  scan.set_aligned(true);
  scan.set_fitness(0.9123);
  scan.set_inlier_rmse(0.00021);
  EXPECT_EQ(FormatScanAlignment(scan), "scan 4 cld_x: fitness 0.912, rmse 0.210 mm");
  scan.set_has_error(true);
  scan.set_rotation_error_deg(0.0121);
  scan.set_translation_error_m(0.00008);
  EXPECT_EQ(FormatScanAlignment(scan),
            "scan 4 cld_x: fitness 0.912, rmse 0.210 mm, rot err 0.012 deg, trans err 0.080 mm");
  scan.set_union_points(48213);
  EXPECT_EQ(FormatScanAlignment(scan),
            "scan 4 cld_x: fitness 0.912, rmse 0.210 mm, rot err 0.012 deg, trans err 0.080 mm, union 48213 points");
  scan.clear_union_points();
  scan.set_aligned(false);
  scan.set_reason("no overlap with the scans aligned so far");
  EXPECT_EQ(FormatScanAlignment(scan), "scan 4 cld_x: NOT aligned: no overlap with the scans aligned so far");
}

}  // namespace
}  // namespace vscan::cli
