// Bin fills through the service layer over a real store: the settled parts become the scene's
// objects in one revision, a scan of the bin carries ground truth that agrees with independent
// counts, and a cancelled fill leaves the scene as it was.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "api/reports/proto_report_writer.h"
#include "jobs/job_runner.h"
#include "service/bins/bin_fill_plan.h"
#include "service/bins/bin_fill_run.h"
#include "service/bins/bin_fill_simulation.h"
#include "service/scan/scan_run.h"
#include "recorded_fill.h"
#include "service_world.h"
#include "tote_mesh.h"

namespace vscan::service {
namespace {

using testing::RecordedFill;

// A whole cloud's instance ids.
class CloudConsumer final : public ScanConsumer {
 public:
  void Begin(uint64_t, std::optional<uint64_t>) override {}
  void Accept(const raycast::RowBlock&) override { ADD_FAILURE() << "a scan with ground truth streamed rows"; }
  bool HasRoom() override { return true; }
  void WaitForRoom() override {}
  Status Cloud(const PointCloud& c) override {
    cloud = c;
    return Status::Ok();
  }
  PointCloud cloud;
};

std::string FixtureBytes(const std::string& file) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/" + file, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::string UploadPart(testing::ServiceWorld& world, const std::string& file, double metres_per_unit) {
  scenes::MeshUpload upload;
  upload.name = file;
  upload.format = geometry::MeshFileFormat::kStl;
  upload.unit = store::LengthUnit::kInch;
  upload.metres_per_unit = metres_per_unit;
  auto mesh = world.context().registry.AddMesh(FixtureBytes(file), upload);
  EXPECT_TRUE(mesh.ok()) << mesh.status().ToString();
  return mesh->mesh_id;
}

// Angle blocks (inches) and round pins (inches, scaled to 7.8 cm) into a 20 x 15 x 10 cm bin.
BinFillRequest Request(testing::ServiceWorld& world, const std::string& scene_id, uint32_t blocks, uint32_t pins) {
  BinFillRequest request;
  request.scene_id = scene_id;
  request.bin.inner_size = Eigen::Vector3d(0.20, 0.15, 0.10);
  request.bin.world_from_bin.translation() = Eigen::Vector3d(0.5, -0.2, 0.0);
  request.options.seed = 11;
  request.options.max_simulated_s = 30;
  if (blocks > 0) {
    BinPartRequest block;
    block.mesh_id = UploadPart(world, "angle_block.STL", 0.0254);
    block.count = blocks;
    block.name = "angle_block";
    request.parts.push_back(block);
  }
  if (pins > 0) {
    BinPartRequest pin;
    pin.mesh_id = UploadPart(world, "round.stl", 0.0254);
    pin.count = pins;
    pin.scale = 0.0013 / 0.0254;
    pin.name = "round";
    request.parts.push_back(pin);
  }
  return request;
}

store::SceneRecord Scene(testing::ServiceWorld& world, const std::string& scene_id) {
  auto scene = world.context().registry.catalogue().GetScene(scene_id);
  EXPECT_TRUE(scene.ok());
  return *scene;
}

// A ray-cast scan from 0.45 m above the bin's floor, looking down, with ground truth.
ScanPlan ScanFromAbove(const std::string& scene_id, const Pose3& world_from_bin) {
  ScanPlan plan;
  plan.scene_id = scene_id;
  plan.camera = sensor::CameraFromFov(320, 240, 50, 0.05, 2.0);
  Pose3 bin_from_sensor = Pose3::Identity();
  bin_from_sensor.translation() = Eigen::Vector3d(0, 0, 0.45);
  bin_from_sensor.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();  // z down, y flipped: rigid
  plan.world_from_sensor = world_from_bin * bin_from_sensor;
  plan.fields = kFieldPosition | kFieldNormal;  // no instance ids asked: ground truth counts them itself
  plan.measurement.fields = plan.fields;
  plan.ground_truth = true;
  return plan;
}

TEST(BinFill, SettledPartsBecomeTheScenesObjectsInOneRevision) {
  testing::ServiceWorld world;
  const std::string scene_id = world.EmptyScene();
  auto plan = PlanBinFill(world.context().registry, Request(world, scene_id, 10, 10));
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const uint64_t revision_before = Scene(world, scene_id).revision;

  RecordedFill recorder;
  jobs::JobControl control;
  RunBinFill(world.context().registry, recorder, "job_test", *plan, control);
  ASSERT_EQ(recorder.end_state, store::JobState::kSucceeded) << recorder.end_message;
  EXPECT_NE(recorder.bin_json.find("\"applied\":true"), std::string::npos);
  // The settled meshes' overlaps, as measured on the parts, within the fill's 0.5 mm bound.
  for (const std::string key : {"\"max_part_part_m\":", "\"max_part_bin_m\":"}) {
    const size_t at = recorder.bin_json.find("\"mesh_overlap\":{");
    ASSERT_NE(at, std::string::npos);
    const size_t value = recorder.bin_json.find(key, at);
    ASSERT_NE(value, std::string::npos) << key;
    EXPECT_LE(std::stod(recorder.bin_json.substr(value + key.size())), 0.0005) << key;
  }
  EXPECT_GE(recorder.messages.size(), 2u);  // the intent and at least one second of progress

  // The same plan simulated again gives the same bits: the poses the job placed.
  const physics::FillResult again = SimulateBinFill(*plan, nullptr, nullptr);
  ASSERT_NE(again.end, physics::FillEnd::kCancelled);
  const store::SceneRecord scene = Scene(world, scene_id);
  EXPECT_EQ(scene.revision, revision_before + 1);
  ASSERT_EQ(scene.objects.size(), 1 + again.parts.size());
  EXPECT_EQ(scene.objects[0].label, "bin");
  EXPECT_TRUE(scene.objects[0].pose.isApprox(plan->request.bin.world_from_bin.matrix()));
  std::map<uint32_t, bool> ids;
  for (size_t i = 0; i < again.parts.size(); ++i) {
    const store::ObjectRecord& object = scene.objects[i + 1];
    const physics::PlacedPart& part = again.parts[i];
    EXPECT_EQ(object.label, plan->parts[part.type].name + "#" + std::to_string(part.instance + 1));
    EXPECT_EQ(object.mesh_id, plan->request.parts[part.type].mesh_id);
    EXPECT_DOUBLE_EQ(object.scale, plan->request.parts[part.type].scale);
    EXPECT_TRUE(object.pose.isApprox(part.world_from_part.matrix(), 1e-12)) << object.label;
    ids[object.instance_id] = true;
  }
  EXPECT_EQ(ids.size(), again.parts.size());  // each its own instance id
}

TEST(BinFill, AScanOfTheBinCarriesGroundTruthThatAgreesWithIndependentCounts) {
  testing::ServiceWorld world;
  const std::string scene_id = world.EmptyScene();
  auto plan = PlanBinFill(world.context().registry, Request(world, scene_id, 10, 10));
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  RecordedFill recorder;
  jobs::JobControl control;
  RunBinFill(world.context().registry, recorder, "job_test", *plan, control);
  ASSERT_EQ(recorder.end_state, store::JobState::kSucceeded) << recorder.end_message;

  CloudConsumer out;
  ScanOutcome outcome;
  const ScanPlan scan = ScanFromAbove(scene_id, plan->request.bin.world_from_bin);
  ASSERT_TRUE(RunScan(world.context(), scan, nullptr, out, &outcome).ok());
  EXPECT_FALSE(out.cloud.Has(kFieldInstanceId));  // counted, but not returned unasked
  EXPECT_EQ(out.cloud.fields, scan.fields);

  // Every returned point belongs to some object: the visible counts add up to the cloud.
  uint64_t visible = 0;
  for (const ObjectTruth& object : outcome.objects) {
    EXPECT_GE(object.visible_fraction, 0.0) << object.label;
    EXPECT_LE(object.visible_fraction, 1.0) << object.label;
    EXPECT_LE(object.visible_points, object.unoccluded_points) << object.label;
    EXPECT_TRUE(object.sensor_from_object.isApprox(scan.world_from_sensor.inverse() * object.world_from_object));
    visible += object.visible_points;
  }
  EXPECT_EQ(visible, out.cloud.size());
  ASSERT_GE(outcome.objects.size(), 10u);
  EXPECT_EQ(outcome.objects[0].label, "bin");

  // Parts high in the pile are seen more than parts low in it (heights of the parts' centroids).
  std::map<std::string, Eigen::Vector3d> centroid_by_mesh;
  for (size_t t = 0; t < plan->parts.size(); ++t) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3f& v : plan->parts[t].mesh.vertices) sum += v.cast<double>();
    centroid_by_mesh[plan->request.parts[t].mesh_id] = sum / static_cast<double>(plan->parts[t].mesh.vertices.size());
  }
  std::vector<std::pair<double, double>> height_and_fraction;
  for (const ObjectTruth& object : outcome.objects) {
    if (object.label == "bin") continue;
    const Eigen::Vector3d centroid = object.world_from_object * centroid_by_mesh.at(object.mesh_id);
    height_and_fraction.emplace_back(centroid.z(), object.visible_fraction);
  }
  std::sort(height_and_fraction.begin(), height_and_fraction.end());
  const size_t third = height_and_fraction.size() / 3;
  double low = 0, high = 0;
  for (size_t i = 0; i < third; ++i) {
    low += height_and_fraction[i].second;
    high += height_and_fraction[height_and_fraction.size() - 1 - i].second;
  }
  EXPECT_GT(high, low);
}

TEST(BinFill, APartAloneInTheBinIsSeenWholeFromAbove) {
  testing::ServiceWorld world;
  const std::string scene_id = world.EmptyScene();
  auto plan = PlanBinFill(world.context().registry, Request(world, scene_id, 1, 0));
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  RecordedFill recorder;
  jobs::JobControl control;
  RunBinFill(world.context().registry, recorder, "job_test", *plan, control);
  ASSERT_EQ(recorder.end_state, store::JobState::kSucceeded) << recorder.end_message;
  const store::SceneRecord scene = Scene(world, scene_id);
  ASSERT_EQ(scene.objects.size(), 2u);
  const store::ObjectRecord& block = scene.objects[1];

  CloudConsumer out;
  ScanOutcome outcome;
  const ScanPlan scan = ScanFromAbove(scene_id, plan->request.bin.world_from_bin);
  ASSERT_TRUE(RunScan(world.context(), scan, nullptr, out, &outcome).ok());
  const auto truth = std::find_if(outcome.objects.begin(), outcome.objects.end(),
                                  [&](const ObjectTruth& o) { return o.object_id == block.object_id; });
  ASSERT_NE(truth, outcome.objects.end());
  EXPECT_GT(truth->visible_fraction, 0.95);

  // The count alone, independently: the same mesh at the same pose in a scene of its own, the
  // same camera, the whole image.
  const std::string alone_id = world.EmptyScene();
  store::ObjectRecord copy = block;
  copy.scene_id = alone_id;
  ASSERT_TRUE(world.context().registry.catalogue().AddObject(copy).ok());
  ScanPlan alone = scan;
  alone.scene_id = alone_id;
  CloudConsumer alone_out;
  ScanOutcome alone_outcome;
  ASSERT_TRUE(RunScan(world.context(), alone, nullptr, alone_out, &alone_outcome).ok());
  EXPECT_EQ(truth->unoccluded_points, alone_out.cloud.size());
  EXPECT_EQ(truth->visible_points, out.cloud.size() - (outcome.objects[0].visible_points));
}

TEST(BinFill, ACancelledFillLeavesTheSceneAsItWas) {
  testing::ServiceWorld world;
  const std::string scene_id = world.EmptyScene();
  auto plan = PlanBinFill(world.context().registry, Request(world, scene_id, 6, 6));
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const store::SceneRecord before = Scene(world, scene_id);

  RecordedFill recorder;
  recorder.stop_when = "simulated";
  RunBinFill(world.context().registry, recorder, "job_test", *plan, recorder.control);
  EXPECT_EQ(recorder.end_state, store::JobState::kCancelled) << recorder.end_message;
  EXPECT_NE(recorder.bin_json.find("\"applied\":false"), std::string::npos);
  EXPECT_NE(recorder.bin_json.find("\"end\":\"cancelled\""), std::string::npos);
  const store::SceneRecord after = Scene(world, scene_id);
  EXPECT_EQ(after.revision, before.revision);
  EXPECT_TRUE(after.objects.empty());
}

TEST(BinFill, UnknownMeshesAndScenesAreNotFoundNamingTheField) {
  testing::ServiceWorld world;
  const std::string scene_id = world.EmptyScene();
  BinFillRequest request = Request(world, scene_id, 1, 1);
  request.parts[1].mesh_id = "msh_0000000000000000";
  auto plan = PlanBinFill(world.context().registry, request);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(plan.status().field(), "parts[1].mesh_id");

  request = Request(world, "scn_0000000000000000", 1, 0);
  plan = PlanBinFill(world.context().registry, request);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().code(), StatusCode::kNotFound);
  EXPECT_TRUE(plan.status().message().starts_with("scene_id")) << plan.status().message();
}

// A mesh as ASCII STL, to upload it as a client would.
std::string AsciiStl(const TriangleMesh& mesh) {
  std::ostringstream out;
  out << "solid tote\n";
  for (const auto& t : mesh.triangles) {
    out << "facet normal 0 0 0\nouter loop\n";
    for (uint32_t i : t) {
      const Eigen::Vector3f& v = mesh.vertices[i];
      out << "vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
    }
    out << "endloop\nendfacet\n";
  }
  out << "endsolid tote\n";
  return out.str();
}

// A 16 x 12 cm tote opening to 22 x 16 cm, 10 cm deep, uploaded in metres.
std::string UploadTote(testing::ServiceWorld& world) {
  scenes::MeshUpload upload;
  upload.name = "tote";
  upload.format = geometry::MeshFileFormat::kStl;
  upload.unit = store::LengthUnit::kMetre;
  upload.metres_per_unit = 1.0;
  auto mesh = world.context().registry.AddMesh(AsciiStl(physics::test::SlopedTote(0.16f, 0.12f, 0.22f, 0.16f, 0.10f)),
                                               upload);
  EXPECT_TRUE(mesh.ok()) << mesh.status().ToString();
  return mesh.ok() ? mesh->mesh_id : "";
}

TEST(BinFill, AMeshBinIsTheBinObjectAndHoldsTheParts) {
  testing::ServiceWorld world;
  const std::string scene_id = world.EmptyScene();
  BinFillRequest request = Request(world, scene_id, 4, 2);
  request.mesh_bin = true;
  request.bin_mesh_id = UploadTote(world);
  request.bin_mesh_scale = 1.0;
  auto plan = PlanBinFill(world.context().registry, request);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  RecordedFill recorder;
  jobs::JobControl control;
  RunBinFill(world.context().registry, recorder, "job_test", *plan, control);
  ASSERT_EQ(recorder.end_state, store::JobState::kSucceeded) << recorder.end_message;
  EXPECT_NE(recorder.bin_json.find("\"mesh_id\":\"" + request.bin_mesh_id + "\""), std::string::npos);
  EXPECT_EQ(recorder.bin_json.find("inner_size"), std::string::npos);

  const store::SceneRecord scene = Scene(world, scene_id);
  ASSERT_EQ(scene.objects.size(), 7u);
  const store::ObjectRecord& bin = scene.objects[0];
  EXPECT_EQ(bin.label, "bin");
  EXPECT_EQ(bin.mesh_id, request.bin_mesh_id);  // the uploaded mesh itself, no new one
  EXPECT_DOUBLE_EQ(bin.scale, 1.0);
  EXPECT_TRUE(bin.pose.isApprox(request.bin.world_from_bin.matrix()));
  EXPECT_EQ(bin.instance_id, 1u);
  const Eigen::Matrix4d bin_from_world = bin.pose.inverse();
  for (size_t i = 1; i < scene.objects.size(); ++i) {
    const Eigen::Vector4d centre = bin_from_world * scene.objects[i].pose.col(3);
    EXPECT_LE(std::abs(centre.x()), 0.11) << scene.objects[i].label;
    EXPECT_LE(std::abs(centre.y()), 0.08) << scene.objects[i].label;
    EXPECT_GE(centre.z(), 0.0) << scene.objects[i].label;
    EXPECT_LE(centre.z(), 0.10) << scene.objects[i].label;
  }
}

TEST(BinFill, AMeshBinIsCheckedNamingItsField) {
  testing::ServiceWorld world;
  const std::string scene_id = world.EmptyScene();
  BinFillRequest request = Request(world, scene_id, 1, 0);
  request.mesh_bin = true;
  request.bin_mesh_id = "msh_0000000000000000";
  auto plan = PlanBinFill(world.context().registry, request);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(plan.status().field(), "bin_mesh.mesh_id");

  // Scaled down to 0.1 mm deep the tote holds no volume.
  request.bin_mesh_id = UploadTote(world);
  request.bin_mesh_scale = 1e-3;
  plan = PlanBinFill(world.context().registry, request);
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(plan.status().field(), "bin_mesh.scale");

  // An opening narrower than the parts: the fill ends full with nothing in the bin.
  request.bin_mesh_scale = 0.1;
  plan = PlanBinFill(world.context().registry, request);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const physics::FillResult result = SimulateBinFill(*plan, nullptr, nullptr);
  EXPECT_EQ(result.end, physics::FillEnd::kFull);
  EXPECT_TRUE(result.parts.empty());
  EXPECT_NE(result.message.find("opening"), std::string::npos) << result.message;
}

}  // namespace
}  // namespace vscan::service
