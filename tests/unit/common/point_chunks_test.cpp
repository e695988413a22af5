#include "vscan/common/point_chunks.h"

#include <gtest/gtest.h>

#include <cstring>

#include "vscan_test/clouds.h"

namespace vscan {
namespace {

using test::MakeCloud;

TEST(PointChunks, PointsPerChunkUsesFieldSizes) {
  EXPECT_EQ(PointsPerChunk(kFieldPosition, 1200), 100u);
  EXPECT_EQ(PointsPerChunk(kFieldsAll, 4000), 100u);
  EXPECT_EQ(PointsPerChunk(kFieldsAll, 1), 1u);
}

TEST(PointChunks, RoundTripOverManyChunks) {
  for (uint32_t fields : {static_cast<uint32_t>(kFieldPosition), static_cast<uint32_t>(kFieldsDefault),
                          static_cast<uint32_t>(kFieldsAll)}) {
    const PointCloud cloud = MakeCloud(fields, 1001);
    const size_t per = PointsPerChunk(fields, 4096);
    PointCloud back;
    back.fields = fields;
    uint32_t index = 0;
    for (size_t begin = 0; begin < cloud.size(); begin += per) {
      v1::PointChunk chunk;
      const size_t count = std::min(per, cloud.size() - begin);
      PackChunk(cloud, begin, count, index++, &chunk);
      EXPECT_EQ(chunk.count(), count);
      EXPECT_EQ(chunk.positions().size(), count * 12);
      // Through the wire encoding too.
      v1::PointChunk parsed;
      ASSERT_TRUE(parsed.ParseFromString(chunk.SerializeAsString()));
      ASSERT_TRUE(AppendChunk(parsed, &back).ok());
    }
    EXPECT_EQ(back.positions, cloud.positions);
    EXPECT_EQ(back.normals, cloud.normals);
    EXPECT_EQ(back.ranges, cloud.ranges);
    EXPECT_EQ(back.intensities, cloud.intensities);
    EXPECT_EQ(back.instance_ids, cloud.instance_ids);
    EXPECT_EQ(back.pixels, cloud.pixels);
  }
}

TEST(PointChunks, CheckChunkNamesTheShortArray) {
  v1::PointChunk chunk;
  PackChunk(MakeCloud(kFieldsDefault, 5), 0, 5, 0, &chunk);
  EXPECT_TRUE(CheckChunk(chunk, kFieldsDefault).ok());
  EXPECT_TRUE(CheckChunk(chunk, kFieldPosition).ok());
  chunk.mutable_ranges()->pop_back();
  const Status short_ranges = CheckChunk(chunk, kFieldsDefault);
  EXPECT_EQ(short_ranges.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(short_ranges.message().find("chunk.ranges"), std::string::npos);
  EXPECT_EQ(CheckChunk(chunk, kFieldsAll).code(), StatusCode::kInvalidArgument);
}

TEST(PointChunks, AbsentFieldsAreNotPacked) {
  v1::PointChunk chunk;
  const PointCloud cloud = MakeCloud(kFieldPosition | kFieldRange, 4);
  PackChunk(cloud, 1, 2, 7, &chunk);
  EXPECT_EQ(chunk.index(), 7u);
  EXPECT_EQ(chunk.ranges().size(), 8u);
  EXPECT_TRUE(chunk.normals().empty());
  EXPECT_TRUE(chunk.pixels().empty());
  float r;
  std::memcpy(&r, chunk.ranges().data(), 4);
  EXPECT_EQ(r, cloud.ranges[1]);
}

TEST(PointChunks, LengthMismatchIsRejectedNamingTheArray) {
  v1::PointChunk chunk;
  PackChunk(MakeCloud(kFieldsDefault, 5), 0, 5, 0, &chunk);
  chunk.mutable_intensities()->pop_back();
  PointCloud back;
  back.fields = kFieldsDefault;
  const Status s = AppendChunk(chunk, &back);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("intensities"), std::string::npos) << s.message();
}

TEST(PointChunks, CountDisagreeingWithBytesIsRejected) {
  v1::PointChunk chunk;
  PackChunk(MakeCloud(kFieldPosition, 5), 0, 5, 0, &chunk);
  chunk.set_count(6);
  PointCloud back;
  EXPECT_EQ(AppendChunk(chunk, &back).code(), StatusCode::kInvalidArgument);
}

TEST(PointChunks, MissingRequestedFieldIsRejected) {
  v1::PointChunk chunk;
  PackChunk(MakeCloud(kFieldPosition, 3), 0, 3, 0, &chunk);
  PointCloud back;
  back.fields = kFieldPosition | kFieldNormal;
  const Status s = AppendChunk(chunk, &back);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("normals"), std::string::npos);
}

}  // namespace
}  // namespace vscan
