#include <fstream>

#include <gtest/gtest.h>

#include "render_test_scenes.h"
#include "vscan_test/clouds.h"
#include "vscan_test/temp_dir.h"
#include "vscan/common/cloud_io.h"
#include "vscan/render/png_io.h"
#include "vscan/render/render_input.h"

namespace vscan::render {
namespace {

TEST(PngIoTest, WritesAndReadsBackEveryByte) {
  vscan::test::TempDir dir;
  Image image(37, 21);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = static_cast<uint8_t>((i * 7919) % 256);
  const std::string path = (dir.path() / "pattern.png").string();
  ASSERT_TRUE(WritePng(image, path).ok());
  const auto back = ReadPng(path);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->width, 37u);
  EXPECT_EQ(back->height, 21u);
  EXPECT_EQ(back->rgb, image.rgb);
  EXPECT_EQ(back->At(3, 2), image.At(3, 2));
}

TEST(PngIoTest, ReportsMissingAndMalformedFiles) {
  vscan::test::TempDir dir;
  EXPECT_EQ(ReadPng((dir.path() / "none.png").string()).status().code(), StatusCode::kNotFound);
  const std::string text = (dir.path() / "text.png").string();
  std::ofstream(text) << "not an image at all";
  EXPECT_EQ(ReadPng(text).status().code(), StatusCode::kInvalidArgument);
  // A valid signature followed by garbage fails inside libpng and comes back as an error.
  const std::string cut = (dir.path() / "cut.png").string();
  std::ofstream(cut, std::ios::binary) << "\x89PNG\r\n\x1a\n garbage";
  EXPECT_EQ(ReadPng(cut).status().code(), StatusCode::kDataLoss);
  EXPECT_EQ(WritePng(Image(4, 4), (dir.path() / "no" / "dir.png").string()).code(), StatusCode::kNotFound);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "no"));
}

PointCloud SampleCloud() {
  PointCloud cloud;
  cloud.fields = kFieldsDefault;
  cloud.Resize(3);
  cloud.positions = {{0, 0, 0}, {1, -2, 3}, {0.5f, 0.25f, -1}};
  cloud.normals = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
  cloud.ranges = {1, 2, 3};
  cloud.intensities = {0.1f, 0.2f, 0.3f};
  cloud.instance_ids = {0, 7, 9};
  return cloud;
}

TEST(RenderInputTest, ReadsCloudsWrittenAsPlyAndPcd) {
  vscan::test::TempDir dir;
  const PointCloud cloud = SampleCloud();
  for (const char* name : {"cloud.ply", "cloud.pcd"}) {
    const std::string path = (dir.path() / name).string();
    ASSERT_TRUE(WriteCloud(cloud, path).ok());
    const auto input = LoadRenderInput(path);
    ASSERT_TRUE(input.ok()) << input.status().message();
    EXPECT_EQ(input->kind, InputKind::kCloud) << name;
    EXPECT_EQ(input->cloud.fields, cloud.fields) << name;
    EXPECT_EQ(input->cloud.positions, cloud.positions) << name;
    EXPECT_EQ(input->cloud.normals, cloud.normals) << name;
    EXPECT_EQ(input->cloud.intensities, cloud.intensities) << name;
    EXPECT_EQ(input->cloud.instance_ids, cloud.instance_ids) << name;
    EXPECT_EQ(input->Count(), 3u);
    EXPECT_EQ(input->bounds.min, Eigen::Vector3f(0, -2, -1)) << name;
    EXPECT_EQ(input->bounds.max, Eigen::Vector3f(1, 0.25f, 3)) << name;
  }
}

// Every `--color` mode (status included) must work on a .pcd as on a .ply.
TEST(RenderInputTest, CloudsKeepEveryFieldInEitherFormat) {
  vscan::test::TempDir dir;
  const PointCloud cloud = vscan::test::MakeCloud(kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal, 50);
  for (const char* name : {"every.ply", "every.pcd"}) {
    const std::string path = (dir.path() / name).string();
    ASSERT_TRUE(WriteCloud(cloud, path).ok());
    const auto input = LoadRenderInput(path);
    ASSERT_TRUE(input.ok()) << input.status().message();
    vscan::test::ExpectSameCloud(input->cloud, cloud);
  }
}

TEST(RenderInputTest, PlyWithFacesIsAMesh) {
  vscan::test::TempDir dir;
  const std::string path = (dir.path() / "quad.ply").string();
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n2 0 0\n2 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  const auto input = LoadRenderInput(path);
  ASSERT_TRUE(input.ok()) << input.status().message();
  EXPECT_EQ(input->kind, InputKind::kMesh);
  EXPECT_EQ(input->Count(), 2u);
  EXPECT_EQ(input->bounds.max, Eigen::Vector3f(2, 1, 0));
}

TEST(RenderInputTest, RejectsUnknownMissingAndEmptyInputs) {
  vscan::test::TempDir dir;
  const auto unknown = LoadRenderInput((dir.path() / "cloud.xyz").string());
  EXPECT_EQ(unknown.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(unknown.status().message().rfind("INPUT", 0), 0u);
  EXPECT_EQ(LoadRenderInput((dir.path() / "none.pcd").string()).status().code(), StatusCode::kNotFound);
  const std::string empty = (dir.path() / "empty.ply").string();
  ASSERT_TRUE(WritePly(PointCloud{}, empty).ok());
  EXPECT_EQ(LoadRenderInput(empty).status().code(), StatusCode::kInvalidArgument);
  const std::string truncated = (dir.path() / "short.pcd").string();
  ASSERT_TRUE(WritePcd(SampleCloud(), truncated).ok());
  std::filesystem::resize_file(truncated, std::filesystem::file_size(truncated) - 5);
  EXPECT_EQ(LoadRenderInput(truncated).status().code(), StatusCode::kDataLoss);
}

}  // namespace
}  // namespace vscan::render
