// The reports vscand writes (model.json, campaign.json, bin.json) against their schema,
// proto/vscan/v1/reports.proto: filled reports print every field the schema has and no key it lacks,
// read back into the same message, and a key spelt otherwise is caught.

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <google/protobuf/util/message_differencer.h>

#include "api/reports/proto_report_writer.h"
#include "api/reports/report_convert.h"
#include "service/bins/bin_fill_plan.h"
#include "service/campaign/campaign_plan.h"
#include "vscan/common/report_json.h"

namespace vscan::api {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Struct;
using google::protobuf::Value;

// Every field path of a message type ("alignment.scans[].pose"); a ListValue is a leaf.
void SchemaPaths(const Descriptor* type, const std::string& prefix, std::set<std::string>* out) {
  for (int i = 0; i < type->field_count(); ++i) {
    const FieldDescriptor* field = type->field(i);
    const std::string path = prefix + field->name();
    out->insert(path);
    if (field->type() == FieldDescriptor::TYPE_MESSAGE &&
        field->message_type() != google::protobuf::ListValue::descriptor()) {
      SchemaPaths(field->message_type(), path + (field->is_repeated() ? "[]." : "."), out);
    }
  }
}

void KeyPaths(const Value& value, const std::string& path, std::set<std::string>* out);

void KeyPaths(const Struct& object, const std::string& prefix, std::set<std::string>* out) {
  for (const auto& [key, value] : object.fields()) {
    out->insert(prefix + key);
    KeyPaths(value, prefix + key, out);
  }
}

void KeyPaths(const Value& value, const std::string& path, std::set<std::string>* out) {
  if (value.has_struct_value()) KeyPaths(value.struct_value(), path + ".", out);
  if (value.has_list_value()) {
    for (const Value& item : value.list_value().values()) {
      if (item.has_struct_value()) KeyPaths(item.struct_value(), path + "[].", out);
    }
  }
}

// The key paths of JSON reports together, read as plain JSON (not through the schema).
std::set<std::string> KeysOf(const std::vector<std::string>& reports) {
  std::set<std::string> keys;
  for (const std::string& text : reports) {
    Struct object;
    EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(text, &object).ok()) << text;
    KeyPaths(object, "", &keys);
  }
  return keys;
}

std::set<std::string> SchemaOf(const Descriptor* type) {
  std::set<std::string> paths;
  SchemaPaths(type, "", &paths);
  return paths;
}

template <typename Message>
void ExpectReadsBack(const std::string& json, const Message& written) {
  Message read;
  ASSERT_TRUE(ParseReport(json, "report", &read).ok()) << json;
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(read, written)) << json;
}

service::ScanAlignmentRecord Scan(uint32_t index, bool aligned) {
  service::ScanAlignmentRecord scan;
  scan.index = index;
  scan.cloud_id = "cld_" + std::to_string(index);
  scan.name = "scan " + std::to_string(index);
  scan.aligned = aligned;
  scan.reason = aligned ? "" : "fitness 0.1 below 0.3";
  scan.fitness = aligned ? 0.9 : 0.1;
  scan.inlier_rmse = 2e-4;
  scan.has_error = true;
  scan.rotation_error_deg = 0.01 * (index + 1);
  scan.translation_error_m = 1e-4 * (index + 1);
  scan.initial_rotation_error_deg = 0.5;
  scan.initial_translation_error_m = 0.002;
  return scan;
}

// Every section run, every optional part there; crop: a box or a cylinder (one or the other).
service::ModelReport FullModelReport(bool box_crop) {
  service::ModelReport report;
  report.job_id = "job_m";
  report.state = "SUCCEEDED";
  report.scene_id = "scn_1";
  report.clouds = 2;
  report.crop = box_crop ? service::BoxCrop({Eigen::Vector3d(-0.1, -0.1, 0), Eigen::Vector3d(0.1, 0.1, 0.2)})
                         : service::ModelCrop{};
  if (!box_crop) {
    report.crop.kind = service::ModelCrop::Kind::kCylinder;
    report.crop.radius = 0.1;
    report.crop.height = 0.2;
  }
  service::ModelAlignmentReport& alignment = report.alignment.emplace();
  alignment.initial_pose = "known";
  alignment.voxel_size = 0.002;
  alignment.seconds = 1.5;
  alignment.scans = {Scan(0, true), Scan(1, false)};
  alignment.artifact = "aligned.ply";
  service::ModelReconstructionReport& mesh = report.reconstruction.emplace();
  mesh.method = "tsdf";
  mesh.voxel_size = 0.001;
  mesh.vertices = 100;
  mesh.triangles = 196;
  mesh.seconds = 2;
  mesh.artifact = "mesh.ply";
  service::ModelEvaluationReport& evaluation = report.evaluation.emplace();
  evaluation.tau = 0.001;
  evaluation.objects = {"obj_1"};
  evaluation.area_m2 = 0.05;
  evaluation.samples = 1000;
  evaluation.union_metrics.f_score = 0.9;
  evaluation.mesh_metrics.emplace().f_score = 0.95;
  evaluation.coverage = 0.93;
  evaluation.uncovered_artifact = "uncovered.ply";
  evaluation.coverage_image = "coverage.png";
  evaluation.next_best_views.push_back({Eigen::Vector3d(0.3, 0, 0.2), Eigen::Vector3d::Zero(), 90, 0.03, 0.96});
  evaluation.next_best_views_note = "1 of 2 asked";
  evaluation.seconds = 3;
  return report;
}

service::CampaignPlan Campaign() {
  service::CampaignPlan plan;
  plan.name = "bunny";
  plan.scene_id = "scn_1";
  plan.mount_id = "mnt_1";
  plan.seed = 7;
  plan.rotations = 2;
  plan.rotation_step_deg = 180;
  service::CampaignViewpoint viewpoint;
  viewpoint.position = Eigen::Vector3d(0.4, 0, 0.2);
  plan.viewpoints = {viewpoint};
  return plan;
}

// A captured step and an unreachable one, both with the arm's state.
std::vector<service::CampaignStepRecord> CampaignSteps() {
  service::CampaignStepRecord captured;
  captured.outcome = "captured";
  captured.seed = 8;
  captured.has_arm = true;
  captured.arm.commanded = Eigen::VectorXd::Zero(6);
  captured.arm.achieved = Eigen::VectorXd::Constant(6, 0.001);
  captured.file = "scan-r00-v00.ply";
  captured.artifact_id = "art_1";
  captured.points = 5000;
  captured.rejected_dark = 120;
  captured.rejected_saturated = 7;
  service::CampaignStepRecord unreachable;
  unreachable.step = 1;
  unreachable.rotation_index = 1;
  unreachable.table_angle_deg = 180;
  unreachable.outcome = "unreachable";
  unreachable.message = "0.2 m short";
  unreachable.miss_distance = 0.2;
  unreachable.has_arm = true;
  unreachable.arm = captured.arm;
  return {captured, unreachable};
}

// One type of part, one part in the bin and one out of it, placed in the scene; a box bin or a mesh bin.
service::BinFillPlan BinPlan(bool mesh_bin) {
  service::BinFillPlan plan;
  plan.request.name = "tote";
  plan.request.scene_id = "scn_1";
  plan.request.mesh_bin = mesh_bin;
  plan.request.bin_mesh_id = mesh_bin ? "msh_bin" : "";
  service::BinPartRequest part;
  part.mesh_id = "msh_part";
  part.count = 2;
  plan.request.parts = {part};
  physics::PartType type;
  type.name = "bracket";
  type.count = 2;
  plan.parts = {type};
  store::MeshRecord mesh;
  mesh.source_unit = store::LengthUnit::kMillimetre;
  plan.meshes = {mesh};
  physics::PartGeometry geometry;
  geometry.mass_kg = 0.05;
  plan.geometry = {geometry};
  return plan;
}

// The part picked (a grasp, the tool, the joints) or covered by another object.
service::BinFillReport BinResult(bool pickable = true) {
  service::BinFillReport report;
  report.job_id = "job_b";
  report.message = "settled";
  physics::FillResult& result = report.result.emplace();
  result.spawned = 2;
  result.message = "every part at rest";
  result.simulated_s = 1.5;
  result.steps = 360;
  result.parts = {physics::PlacedPart{0, 0, Pose3::Identity()}};
  result.outside = {physics::PlacedPart{0, 1, Pose3::Identity()}};
  service::BinPlacement& placement = report.placement.emplace();
  placement.bin.object_id = "obj_bin";
  placement.bin.mesh_id = "msh_box";
  placement.bin.label = "tote";
  placement.bin.instance_id = 1;
  store::ObjectRecord part;
  part.object_id = "obj_p";
  part.label = "bracket#1";
  part.instance_id = 2;
  placement.parts = {part};
  placement.revision = 4;
  service::BinPicks& picks = report.picks.emplace();
  picks.mount_id = "mnt_1";
  picks.gripper = "suction";
  picks.grasps_generated = 12;
  picks.elapsed_s = 0.5;
  service::BinPartPick pick{"obj_p", {}, {}};
  pick.verdict.pickable = pickable;
  if (pickable) {
    pick.verdict.grasp = 0;
    pick.verdict.joint_positions = Eigen::VectorXd::Zero(6);
  } else {
    pick.verdict.failure = grasping::PickFailure::kCovered;
    pick.verdict.detail = "under obj_q";
    pick.covered_by_object_id = "obj_q";
  }
  picks.parts = {pick};
  return report;
}

TEST(ReportSchema, AFullModelReportPrintsEveryFieldOfTheSchemaAndNoOther) {
  const ProtoReportWriter writer;
  const std::string box = writer.ModelJson(FullModelReport(true));
  const std::string cylinder = writer.ModelJson(FullModelReport(false));
  EXPECT_EQ(KeysOf({box, cylinder}), SchemaOf(v1::ModelReport::descriptor()));
  ExpectReadsBack(box, ModelReportMessage(FullModelReport(true)));
  ExpectReadsBack(cylinder, ModelReportMessage(FullModelReport(false)));
}

TEST(ReportSchema, AFullCampaignReportPrintsEveryFieldOfTheSchemaAndNoOther) {
  const std::string json = ProtoReportWriter().CampaignJson("job_c", "SUCCEEDED", Campaign(), CampaignSteps());
  EXPECT_EQ(KeysOf({json}), SchemaOf(v1::CampaignReport::descriptor()));
  ExpectReadsBack(json, CampaignReportMessage("job_c", "SUCCEEDED", Campaign(), CampaignSteps()));
}

TEST(ReportSchema, AFullBinReportPrintsEveryFieldOfTheSchemaAndNoOther) {
  const ProtoReportWriter writer;
  const std::string box = writer.BinFillJson(BinPlan(false), BinResult(true));
  const std::string mesh = writer.BinFillJson(BinPlan(true), BinResult(false));
  EXPECT_EQ(KeysOf({box, mesh}), SchemaOf(v1::BinReport::descriptor()));
  ExpectReadsBack(box, BinReportMessage(BinPlan(false), BinResult(true)));
  ExpectReadsBack(mesh, BinReportMessage(BinPlan(true), BinResult(false)));
}

TEST(ReportSchema, KeysStayAsTheFilesAlwaysHadThem) {
  // snake_case names, counts as numbers (not the strings proto3 JSON gives 64-bit integers), a
  // section that did not run left out, a default value still printed.
  service::ModelReport report = FullModelReport(true);
  report.reconstruction.reset();
  report.alignment->voxel_size = 0;
  const std::string json = ProtoReportWriter().ModelJson(report);
  EXPECT_NE(json.find("\"scene_id\":\"scn_1\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"clouds\":2"), std::string::npos) << json;
  EXPECT_NE(json.find("\"voxel_size\":0"), std::string::npos) << json;
  EXPECT_NE(json.find("\"f_score\":0.9"), std::string::npos) << json;
  EXPECT_EQ(json.find("reconstruction"), std::string::npos) << json;
  EXPECT_EQ(json.back(), '\n');
  const std::string bin = ProtoReportWriter().BinFillJson(BinPlan(false), BinResult());
  EXPECT_NE(bin.find("\"seed\":1,"), std::string::npos) << bin;
  EXPECT_NE(bin.find("\"scene_revision\":4"), std::string::npos) << bin;
  EXPECT_NE(bin.find("\"steps\":360"), std::string::npos) << bin;
  EXPECT_EQ(bin.find("bounds_min"), std::string::npos) << bin;  // a box bin has no mesh bounds
}

TEST(ReportSchema, AKeySpeltOtherwiseIsCaughtAndNotRead) {
  // A writer that renamed f_score would leave a key the schema lacks and a field unread: the key
  // check names both, and a reader through the schema sees no F-score.
  const std::string written = ProtoReportWriter().ModelJson(FullModelReport(true));
  std::string renamed = written;
  for (size_t at = renamed.find("\"f_score\""); at != std::string::npos; at = renamed.find("\"f_score\"", at)) {
    renamed.replace(at, 9, "\"fscore\"");
  }
  const std::set<std::string> keys = KeysOf({renamed, ProtoReportWriter().ModelJson(FullModelReport(false))});
  const std::set<std::string> schema = SchemaOf(v1::ModelReport::descriptor());
  EXPECT_NE(keys, schema);
  EXPECT_TRUE(keys.contains("evaluation.union.fscore"));
  EXPECT_FALSE(schema.contains("evaluation.union.fscore"));
  v1::ModelReport read;
  ASSERT_TRUE(ParseReport(renamed, "model.json", &read).ok());
  EXPECT_EQ(read.evaluation().union_().f_score(), 0.0);
  EXPECT_GT(read.evaluation().union_().precision() + read.evaluation().coverage(), 0.0);
  ASSERT_TRUE(ParseReport(written, "model.json", &read).ok());
  EXPECT_EQ(read.evaluation().union_().f_score(), 0.9);
}

TEST(ReportSchema, WhatTheSchemaCannotReadIsDataLoss) {
  v1::ModelReport read;
  EXPECT_EQ(ParseReport("[1, 2]", "model.json", &read).code(), StatusCode::kDataLoss);
  EXPECT_EQ(ParseReport("{\"clouds\": \"two\"}", "model.json", &read).code(), StatusCode::kDataLoss);
  const Status status = ParseReport("{\"clouds\": ", "model.json", &read);
  EXPECT_NE(status.message().find("model.json"), std::string::npos) << status.message();
}

}  // namespace
}  // namespace vscan::api
