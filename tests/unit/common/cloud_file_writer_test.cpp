#include "vscan/common/cloud_file_writer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "vscan/common/cloud_io.h"
#include "vscan_test/clouds.h"
#include "vscan_test/read_all.h"
#include "vscan_test/temp_dir.h"

namespace vscan {
namespace {

using test::ExpectSameCloud;
using test::MakeCloud;

namespace fs = std::filesystem;

class CloudFileWriterTest : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const { return (dir_.path() / name).string(); }
  size_t Files() const {
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_.path())) ++n;
    return n;
  }

  test::TempDir dir_;
};

using test::ReadAll;

// Points [begin, begin + n) of cloud as a cloud of their own.
PointCloud Slice(const PointCloud& cloud, size_t begin, size_t n) {
  PointCloud out;
  out.fields = cloud.fields;
  const auto take = [&](const auto& from, auto& to) {
    if (!from.empty()) to.assign(from.begin() + begin, from.begin() + begin + n);
  };
  take(cloud.positions, out.positions);
  take(cloud.normals, out.normals);
  take(cloud.ranges, out.ranges);
  take(cloud.intensities, out.intensities);
  take(cloud.instance_ids, out.instance_ids);
  take(cloud.pixels, out.pixels);
  take(cloud.clean_positions, out.clean_positions);
  take(cloud.incidence_angles, out.incidence_angles);
  take(cloud.statuses, out.statuses);
  take(cloud.estimated_normals, out.estimated_normals);
  return out;
}

Status WriteInBlocks(const PointCloud& cloud, const std::string& path, CloudFileFormat format, size_t block) {
  ASSIGN_OR_RETURN(CloudFileWriter writer, CloudFileWriter::Open(path, format, cloud.fields));
  for (size_t begin = 0; begin < cloud.size(); begin += block) {
    RETURN_IF_ERROR(writer.Append(Slice(cloud, begin, std::min(block, cloud.size() - begin))));
  }
  return writer.Finish();
}

TEST_F(CloudFileWriterTest, PlyOfUnknownCountReadsBackWhole) {
  const PointCloud cloud = MakeCloud(kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal, 40000);
  ASSERT_TRUE(WriteInBlocks(cloud, Path("s.ply"), CloudFileFormat::kPly, 7001).ok());
  auto back = ReadPly(Path("s.ply"));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ExpectSameCloud(cloud, *back);
  const std::string data = ReadAll(Path("s.ply"));
  EXPECT_EQ(data.substr(0, 43), "ply\nformat binary_little_endian 1.0\ncomment");
  EXPECT_NE(data.find("\nelement vertex 40000\n"), std::string::npos);
  EXPECT_EQ(Files(), 1u);
}

TEST_F(CloudFileWriterTest, PcdOfUnknownCountHasTheCountAndTheSameBody) {
  const PointCloud cloud = MakeCloud(kFieldsAll, 1000);
  ASSERT_TRUE(WriteInBlocks(cloud, Path("s.pcd"), CloudFileFormat::kPcd, 333).ok());
  ASSERT_TRUE(WritePcd(cloud, Path("w.pcd")).ok());
  const std::string streamed = ReadAll(Path("s.pcd"));
  const std::string whole = ReadAll(Path("w.pcd"));
  EXPECT_EQ(streamed.substr(0, 43), "# .PCD v0.7 - Point Cloud Data file format ");
  EXPECT_NE(streamed.find("\nWIDTH 1000\n"), std::string::npos);
  EXPECT_NE(streamed.find("\nPOINTS 1000\nDATA binary\n"), std::string::npos);
  const std::string body = whole.substr(whole.find("DATA binary\n") + 12);
  ASSERT_EQ(body.size(), 1000u * 40);
  EXPECT_EQ(streamed.substr(streamed.size() - body.size()), body);
}

TEST_F(CloudFileWriterTest, NoPointsIsAValidFile) {
  const PointCloud empty = MakeCloud(kFieldPosition, 0);
  ASSERT_TRUE(WriteInBlocks(empty, Path("e.ply"), CloudFileFormat::kPly, 10).ok());
  auto back = ReadPly(Path("e.ply"));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->size(), 0u);
}

TEST_F(CloudFileWriterTest, UnfinishedFileIsRemoved) {
  {
    auto writer = CloudFileWriter::Open(Path("u.ply"), CloudFileFormat::kPly, kFieldPosition);
    ASSERT_TRUE(writer.ok());
    ASSERT_TRUE(writer->Append(MakeCloud(kFieldPosition, 10)).ok());
  }
  EXPECT_EQ(Files(), 0u);
}

TEST_F(CloudFileWriterTest, AnnouncedCountMustBeMet) {
  auto writer = CloudFileWriter::Open(Path("a.ply"), CloudFileFormat::kPly, kFieldPosition, 5);
  ASSERT_TRUE(writer.ok());
  ASSERT_TRUE(writer->Append(MakeCloud(kFieldPosition, 4)).ok());
  EXPECT_EQ(writer->Finish().code(), StatusCode::kDataLoss);
  EXPECT_EQ(Files(), 0u);
}

TEST_F(CloudFileWriterTest, BlocksMustCarryTheFilesFields) {
  auto writer = CloudFileWriter::Open(Path("f.ply"), CloudFileFormat::kPly, kFieldsDefault);
  ASSERT_TRUE(writer.ok());
  EXPECT_EQ(writer->Append(MakeCloud(kFieldPosition, 3)).code(), StatusCode::kInvalidArgument);
}

TEST_F(CloudFileWriterTest, FormatFollowsTheExtension) {
  EXPECT_EQ(CloudFileFormatOf("a/b.PLY"), CloudFileFormat::kPly);
  EXPECT_EQ(CloudFileFormatOf("b.pcd"), CloudFileFormat::kPcd);
  EXPECT_FALSE(CloudFileFormatOf("b.xyz").has_value());
}

}  // namespace
}  // namespace vscan
