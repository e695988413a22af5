#include "robot_registry/bundle_codec.h"

#include <gtest/gtest.h>

namespace vscan::robot_registry {
namespace {

TEST(BundleCodecTest, RoundTripsInPathOrder) {
  robot::BundleFiles files;
  files.emplace("robot.urdf", "<robot name='r'/>");
  files.emplace("meshes/a.stl", std::string("\0\1\2binary", 9));
  files.emplace("empty", "");
  const std::string blob = EncodeBundle(files);
  auto decoded = DecodeBundle(blob);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  ASSERT_EQ(decoded->size(), 3u);
  size_t i = 0;
  for (const auto& [path, bytes] : files) {
    EXPECT_EQ((*decoded)[i].path, path);
    EXPECT_EQ((*decoded)[i].bytes, bytes);
    ++i;
  }
  EXPECT_EQ(EncodeBundle(files), blob);
}

TEST(BundleCodecTest, RejectsDamagedBlobs) {
  robot::BundleFiles files;
  files.emplace("robot.urdf", "<robot name='r'/>");
  const std::string blob = EncodeBundle(files);
  for (size_t cut = 0; cut < blob.size(); ++cut) {
    EXPECT_EQ(DecodeBundle(blob.substr(0, cut)).status().code(), StatusCode::kDataLoss) << cut;
  }
  EXPECT_EQ(DecodeBundle(blob + "x").status().code(), StatusCode::kDataLoss);
  std::string wrong_version = blob;
  wrong_version[4] = 2;
  EXPECT_EQ(DecodeBundle(wrong_version).status().code(), StatusCode::kDataLoss);
  std::string huge_count = blob;
  huge_count[8] = '\xff';
  huge_count[9] = '\xff';
  EXPECT_EQ(DecodeBundle(huge_count).status().code(), StatusCode::kDataLoss);
}

}  // namespace
}  // namespace vscan::robot_registry
