// RasterScan's contract besides accuracy: caching, threads, cancellation, limits, errors, fields,
// frames and clipping.
#include <atomic>
#include <cstdlib>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "raster/raster_scanner.h"
#include "raster_test_scenes.h"
#include "vscan_test/meshes.h"

namespace vscan::raster {
namespace {

raycast::SceneInstance PlaneAt(double z, double half_side, uint32_t id) {
  raycast::SceneInstance plane;
  plane.mesh = vscan::test::Share(vscan::test::MakeGrid(half_side, 4));
  plane.world_from_object = Eigen::Translation3d(0, 0, z) * Pose3::Identity();
  plane.instance_id = id;
  return plane;
}

struct Fixture {
  sensor::PinholeCamera camera = sensor::CameraFromFov(160, 120, 50.0, 0.05, 10.0);
  Pose3 world_from_sensor = *PoseFromLookAt({0.2, 0.1, -0.3}, {0.0, 0.0, 1.0}, -Eigen::Vector3d::UnitY(), "test");
  std::vector<raycast::SceneInstance> instances = {PlaneAt(1.0, 2.0, 1), PlaneAt(0.6, 0.1, 2)};
};

void ExpectSameCloud(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.positions[i], b.positions[i]) << i;
    ASSERT_EQ(a.instance_ids[i], b.instance_ids[i]) << i;
  }
}

TEST(RasterScan, ReusesTheUploadUntilTheInstancesChange) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  Fixture f;
  RasterStats stats;
  ASSERT_TRUE(RasterScan(*renderer, "cache", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {}, &stats).ok());
  EXPECT_TRUE(stats.scene_uploaded);
  auto before = RasterScan(*renderer, "cache", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {}, &stats);
  ASSERT_TRUE(before.ok());
  EXPECT_FALSE(stats.scene_uploaded);

  // A moved instance under the same key is uploaded again and seen where it now is.
  f.instances[1].world_from_object = Eigen::Translation3d(0, 0, 0.8) * Pose3::Identity();
  auto after = RasterScan(*renderer, "cache", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {}, &stats);
  ASSERT_TRUE(after.ok());
  EXPECT_TRUE(stats.scene_uploaded);
  EXPECT_NE(before->size(), 0u);
  EXPECT_NE(before->positions, after->positions);

  // So is a different mesh object with the same contents.
  f.instances[1].mesh = std::make_shared<const TriangleMesh>(*f.instances[1].mesh);
  ASSERT_TRUE(RasterScan(*renderer, "cache", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {}, &stats).ok());
  EXPECT_TRUE(stats.scene_uploaded);

  const size_t cached = renderer->cached_scene_count();
  renderer->Evict("cache");
  EXPECT_EQ(renderer->cached_scene_count(), cached - 1);
}

TEST(RasterScan, KeepsAtMostTheConfiguredScenes) {
  RendererOptions options;
  options.max_cached_scenes = 2;
  auto renderer = RasterRenderer::Create(options);
  ASSERT_TRUE(renderer.ok()) << renderer.status().ToString();
  Fixture f;
  for (const char* key : {"a", "b", "c"}) {
    ASSERT_TRUE(RasterScan(**renderer, key, f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {}).ok());
  }
  EXPECT_EQ((*renderer)->cached_scene_count(), 2u);
  RasterStats stats;
  ASSERT_TRUE(RasterScan(**renderer, "c", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {}, &stats).ok());
  EXPECT_FALSE(stats.scene_uploaded);
  ASSERT_TRUE(RasterScan(**renderer, "a", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {}, &stats).ok());
  EXPECT_TRUE(stats.scene_uploaded) << "the least recently used scene was dropped";
}

TEST(RasterScan, ServesCallersOnManyThreads) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  const Fixture f;
  std::vector<PointCloud> reference;
  for (RasterMethod method : {RasterMethod::kDepthBuffer, RasterMethod::kColourBuffer}) {
    auto cloud = RasterScan(*renderer, "threads", f.instances, f.camera, f.world_from_sensor, method, {});
    ASSERT_TRUE(cloud.ok());
    reference.push_back(std::move(*cloud));
  }
  std::vector<std::vector<PointCloud>> results(4);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < results.size(); ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 6; ++i) {
        const auto method = i % 2 == 0 ? RasterMethod::kDepthBuffer : RasterMethod::kColourBuffer;
        auto cloud = RasterScan(*renderer, "threads", f.instances, f.camera, f.world_from_sensor, method, {});
        results[t].push_back(cloud.ok() ? std::move(*cloud) : PointCloud{});
      }
    });
  }
  for (auto& t : threads) t.join();
  for (const auto& per_thread : results) {
    for (size_t i = 0; i < per_thread.size(); ++i) ExpectSameCloud(per_thread[i], reference[i % 2]);
  }
}

TEST(RasterScan, StopsWhenCancelled) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  const Fixture f;
  std::atomic<bool> cancel{true};
  RasterOptions options;
  options.cancel = &cancel;
  auto cloud = RasterScan(*renderer, "cancel", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, options);
  ASSERT_FALSE(cloud.ok());
  EXPECT_EQ(cloud.status().code(), StatusCode::kCancelled);
}

TEST(RasterScan, RefusesFramesPastTheLimits) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  Fixture f;
  f.camera.width = renderer->max_side() + 1;
  auto wide = RasterScan(*renderer, "limits", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {});
  ASSERT_FALSE(wide.ok());
  EXPECT_EQ(wide.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(wide.status().message().rfind("camera.width", 0), 0u) << wide.status().message();

  f.camera.width = 160;
  RasterOptions options;
  options.max_pixels = 1000;
  auto many = RasterScan(*renderer, "limits", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, options);
  ASSERT_FALSE(many.ok());
  EXPECT_EQ(many.status().code(), StatusCode::kResourceExhausted);
}

TEST(RasterScan, NamesTheBadField) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  Fixture f;
  Pose3 nan_pose = f.world_from_sensor;
  nan_pose.translation().x() = std::nan("");
  auto bad_pose = RasterScan(*renderer, "bad", f.instances, f.camera, nan_pose, RasterMethod::kDepthBuffer, {});
  EXPECT_EQ(bad_pose.status().code(), StatusCode::kInvalidArgument);

  f.instances[1].mesh = nullptr;
  auto no_mesh = RasterScan(*renderer, "bad", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {});
  EXPECT_EQ(no_mesh.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(no_mesh.status().message(), "instances[1].mesh: missing");

  auto broken = std::make_shared<TriangleMesh>(vscan::test::MakeGrid(1.0, 1));
  broken->triangles[1][2] = 9;
  f.instances[1].mesh = broken;
  auto bad_index = RasterScan(*renderer, "bad", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, {});
  EXPECT_EQ(bad_index.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(bad_index.status().message().rfind("instances[1].mesh.triangles[1]", 0), 0u) << bad_index.status().message();
}

TEST(RasterScan, EmptyScenesAndScenesOutOfRangeGiveEmptyClouds) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  const Fixture f;
  for (RasterMethod method : {RasterMethod::kDepthBuffer, RasterMethod::kColourBuffer}) {
    auto none = RasterScan(*renderer, "empty", {}, f.camera, f.world_from_sensor, method, {});
    ASSERT_TRUE(none.ok()) << none.status().ToString();
    EXPECT_EQ(none->size(), 0u);
    const std::vector<raycast::SceneInstance> behind = {PlaneAt(-5.0, 1.0, 1)};
    auto hidden = RasterScan(*renderer, "behind", behind, f.camera, Pose3::Identity(), method, {});
    ASSERT_TRUE(hidden.ok()) << hidden.status().ToString();
    EXPECT_EQ(hidden->size(), 0u);
  }
}

TEST(RasterScan, FillsOnlyTheRequestedFieldsInPixelOrder) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  const Fixture f;
  RasterOptions options;
  options.fields = kFieldPosition;
  auto bare = RasterScan(*renderer, "fields", f.instances, f.camera, f.world_from_sensor, RasterMethod::kColourBuffer, options);
  ASSERT_TRUE(bare.ok());
  EXPECT_GT(bare->size(), 0u);
  EXPECT_TRUE(bare->normals.empty() && bare->ranges.empty() && bare->intensities.empty() &&
              bare->instance_ids.empty() && bare->pixels.empty());

  options.fields = kFieldsAll;
  auto all = RasterScan(*renderer, "fields", f.instances, f.camera, f.world_from_sensor, RasterMethod::kColourBuffer, options);
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->size(), bare->size());
  EXPECT_EQ(all->positions, bare->positions);
  EXPECT_EQ(all->pixels.size(), all->size());
  for (size_t i = 1; i < all->size(); ++i) ASSERT_LT(all->pixels[i - 1], all->pixels[i]);
  for (size_t i = 0; i < all->size(); ++i) ASSERT_NEAR(all->normals[i].norm(), 1.0f, 1e-6f);
}

TEST(RasterScan, WorldAndSensorFramesDifferByThePose) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  const Fixture f;
  RasterOptions options;
  options.fields = kFieldsAll;
  auto world = RasterScan(*renderer, "frames", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, options);
  options.frame = raycast::ScanFrame::kSensor;
  auto sensor = RasterScan(*renderer, "frames", f.instances, f.camera, f.world_from_sensor, RasterMethod::kDepthBuffer, options);
  ASSERT_TRUE(world.ok() && sensor.ok());
  ASSERT_EQ(world->size(), sensor->size());
  for (size_t i = 0; i < world->size(); ++i) {
    const Eigen::Vector3d p = f.world_from_sensor * sensor->positions[i].cast<double>();
    ASSERT_LT((p - world->positions[i].cast<double>()).norm(), 1e-5);
    const Eigen::Vector3d n = f.world_from_sensor.linear() * sensor->normals[i].cast<double>();
    ASSERT_LT((n - world->normals[i].cast<double>()).norm(), 1e-5);
    // Facing the sensor: the normal points back along the ray.
    ASSERT_LT(sensor->normals[i].dot(sensor->positions[i]), 0.0f);
  }
}

TEST(RasterScan, ClipsAtTheCamerasNearAndFarLikeTheRayCaster) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  // A small plane at 0.6 m in front of a large one at 2 m, camera on the axis.
  const std::vector<raycast::SceneInstance> instances = {PlaneAt(2.0, 3.0, 1), PlaneAt(0.6, 0.1, 2)};
  sensor::PinholeCamera camera = sensor::CameraFromFov(160, 120, 50.0, 1.0, 10.0);
  RasterOptions options;
  options.fields = kFieldsAll;
  options.frame = raycast::ScanFrame::kSensor;
  for (RasterMethod method : {RasterMethod::kDepthBuffer, RasterMethod::kColourBuffer}) {
    auto seen = RasterScan(*renderer, "clip", instances, camera, Pose3::Identity(), method, options);
    ASSERT_TRUE(seen.ok());
    EXPECT_EQ(seen->size(), camera.pixel_count()) << "the near plane hides the small plane, not what is behind it";
    for (size_t i = 0; i < seen->size(); ++i) {
      ASSERT_EQ(seen->instance_ids[i], 1u);
      ASSERT_GE(seen->positions[i].z(), camera.near);
      ASSERT_LE(seen->positions[i].z(), camera.far);
    }
  }
  camera.near = 0.05;
  camera.far = 1.5;
  auto near_only = RasterScan(*renderer, "clip", instances, camera, Pose3::Identity(), RasterMethod::kDepthBuffer, options);
  ASSERT_TRUE(near_only.ok());
  EXPECT_GT(near_only->size(), 0u);
  for (size_t i = 0; i < near_only->size(); ++i) ASSERT_EQ(near_only->instance_ids[i], 2u);
}

TEST(RasterRendererDeathTest, UnavailableWithoutAnEglDisplay) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // a fresh process, before EGL loads its vendors
  EXPECT_EXIT(
      {
        setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/egl_vendor.json", 1);
        auto renderer = RasterRenderer::Create();
        const bool unavailable = !renderer.ok() && renderer.status().code() == StatusCode::kUnavailable &&
                                 renderer.status().message().rfind("raster: no EGL display", 0) == 0;
        std::fprintf(stderr, "%s\n", renderer.ok() ? "created" : renderer.status().ToString().c_str());
        std::exit(unavailable ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "raster: no EGL display");
}

}  // namespace
}  // namespace vscan::raster
