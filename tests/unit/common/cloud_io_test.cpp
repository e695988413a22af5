#include "vscan/common/cloud_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>
#include <cstring>
#include <utility>

#include <unistd.h>

#include "vscan/common/text_excerpt.h"
#include "vscan_test/clouds.h"
#include "vscan_test/read_all.h"

namespace vscan {
namespace {

using test::ExpectSameCloud;
using test::MakeCloud;

namespace fs = std::filesystem;

class CloudIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("vscan_cloud_io_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

using test::ReadAll;

// Every field a scan can carry, ground truth included.
constexpr uint32_t kEveryField = kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal;

TEST_F(CloudIoTest, PlyAndPcdRoundTripEveryField) {
  // More points than one internal write or read block.
  const PointCloud cloud = MakeCloud(kEveryField, 40000);
  for (const char* name : {"all.ply", "all.pcd"}) {
    ASSERT_TRUE(WriteCloud(cloud, Path(name)).ok()) << name;
    const auto back = ReadCloud(Path(name));
    ASSERT_TRUE(back.ok()) << back.status().ToString();
    ExpectSameCloud(cloud, *back);
  }
}

TEST_F(CloudIoTest, PlyAndPcdRoundTripEachFieldAlone) {
  for (uint32_t field = kFieldNormal; field <= kFieldEstimatedNormal; field <<= 1) {
    const PointCloud cloud = MakeCloud(kFieldPosition | field, 9);
    ASSERT_TRUE(WritePly(cloud, Path("one.ply")).ok());
    ASSERT_TRUE(WritePcd(cloud, Path("one.pcd")).ok());
    const auto ply = ReadPly(Path("one.ply"));
    const auto pcd = ReadPcd(Path("one.pcd"));
    ASSERT_TRUE(ply.ok()) << ply.status().ToString();
    ASSERT_TRUE(pcd.ok()) << pcd.status().ToString();
    SCOPED_TRACE("field " + std::to_string(field));
    ExpectSameCloud(cloud, *ply);
    ExpectSameCloud(cloud, *pcd);
  }
}

TEST_F(CloudIoTest, PlyAndPcdRoundTripPositionsOnlyAndEmpty) {
  for (size_t n : {0u, 1u, 3u}) {
    const PointCloud cloud = MakeCloud(kFieldPosition, n);
    for (const char* name : {"p.ply", "p.pcd"}) {
      ASSERT_TRUE(WriteCloud(cloud, Path(name)).ok());
      const auto back = ReadCloud(Path(name));
      ASSERT_TRUE(back.ok()) << back.status().ToString();
      ExpectSameCloud(cloud, *back);
    }
  }
}

TEST_F(CloudIoTest, PlyHeaderListsOnlyPresentFields) {
  const PointCloud cloud = MakeCloud(kFieldPosition | kFieldRange | kFieldPixel, 2);
  ASSERT_TRUE(WritePly(cloud, Path("h.ply")).ok());
  const std::string data = ReadAll(Path("h.ply"));
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty float range\nproperty int pixel\nend_header\n";
  ASSERT_GE(data.size(), header.size());
  EXPECT_EQ(data.substr(0, header.size()), header);
  EXPECT_EQ(data.size(), header.size() + 2 * (3 * 4 + 4 + 4));
}

TEST_F(CloudIoTest, PcdHeaderAndSize) {
  const size_t n = 123;
  const PointCloud cloud = MakeCloud(kFieldsAll, n);
  ASSERT_TRUE(WritePcd(cloud, Path("c.pcd")).ok());
  const std::string data = ReadAll(Path("c.pcd"));
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n"
      "FIELDS x y z normal_x normal_y normal_z range intensity instance pixel\n"
      "SIZE 4 4 4 4 4 4 4 4 4 4\n"
      "TYPE F F F F F F F F I I\n"
      "COUNT 1 1 1 1 1 1 1 1 1 1\n"
      "WIDTH 123\n"
      "HEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS 123\n"
      "DATA binary\n";
  ASSERT_GE(data.size(), header.size());
  EXPECT_EQ(data.substr(0, header.size()), header);
  EXPECT_EQ(data.size(), header.size() + n * 40);
  // First record: x y z of point 0, then its normal.
  float first[6];
  std::memcpy(first, data.data() + header.size(), sizeof(first));
  EXPECT_EQ(first[0], cloud.positions[0].x());
  EXPECT_EQ(first[2], cloud.positions[0].z());
  EXPECT_EQ(first[3], cloud.normals[0].x());
  uint32_t last_pixel;
  std::memcpy(&last_pixel, data.data() + data.size() - 4, 4);
  EXPECT_EQ(last_pixel, cloud.pixels[n - 1]);
}

TEST_F(CloudIoTest, PcdPositionsOnlyHeader) {
  ASSERT_TRUE(WritePcd(MakeCloud(kFieldPosition, 5), Path("p.pcd")).ok());
  const std::string data = ReadAll(Path("p.pcd"));
  EXPECT_NE(data.find("\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 5\n"), std::string::npos);
  EXPECT_EQ(data.size() - data.find("DATA binary\n") - 12, 5u * 12);
}

TEST_F(CloudIoTest, WriteCloudPicksWriterByExtension) {
  const PointCloud cloud = MakeCloud(kFieldsDefault, 4);
  ASSERT_TRUE(WriteCloud(cloud, Path("a.PLY")).ok());
  EXPECT_EQ(ReadAll(Path("a.PLY")).substr(0, 4), "ply\n");
  ASSERT_TRUE(WriteCloud(cloud, Path("a.pcd")).ok());
  EXPECT_EQ(ReadAll(Path("a.pcd")).substr(0, 7), "# .PCD ");
  EXPECT_EQ(WriteCloud(cloud, Path("a.xyz")).code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(fs::exists(Path("a.xyz")));
}

TEST_F(CloudIoTest, WriteLeavesNoTemporaryFiles) {
  ASSERT_TRUE(WritePly(MakeCloud(kFieldsDefault, 10), Path("x.ply")).ok());
  size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++files;
  EXPECT_EQ(files, 1u);
}

TEST_F(CloudIoTest, WriteIntoMissingDirectoryFails) {
  const Status s = WritePly(MakeCloud(kFieldPosition, 1), Path("missing/x.ply"));
  EXPECT_EQ(s.code(), StatusCode::kNotFound) << s.ToString();
}

TEST_F(CloudIoTest, InconsistentCloudIsRejected) {
  PointCloud cloud = MakeCloud(kFieldsDefault, 3);
  cloud.ranges.pop_back();
  const Status s = WritePly(cloud, Path("bad.ply"));
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("ranges"), std::string::npos);
}

TEST_F(CloudIoTest, ReadMissingFileIsNotFound) {
  EXPECT_EQ(ReadPly(Path("nope.ply")).status().code(), StatusCode::kNotFound);
  EXPECT_EQ(ReadPcd(Path("nope.pcd")).status().code(), StatusCode::kNotFound);
}

TEST_F(CloudIoTest, ReadTruncatedFileIsDataLoss) {
  for (const char* name : {"t.ply", "t.pcd"}) {
    ASSERT_TRUE(WriteCloud(MakeCloud(kFieldsDefault, 10), Path(name)).ok());
    fs::resize_file(Path(name), fs::file_size(Path(name)) - 5);
    EXPECT_EQ(ReadCloud(Path(name)).status().code(), StatusCode::kDataLoss) << name;
  }
}

TEST_F(CloudIoTest, ReadCloudPicksReaderByExtension) {
  const PointCloud cloud = MakeCloud(kFieldsDefault, 4);
  ASSERT_TRUE(WritePcd(cloud, Path("a.PCD")).ok());
  const auto back = ReadCloud(Path("a.PCD"));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ExpectSameCloud(cloud, *back);
  std::ofstream(Path("a.xyz")) << "1 2 3\n";
  EXPECT_EQ(ReadCloud(Path("a.xyz")).status().code(), StatusCode::kInvalidArgument);
}

TEST_F(CloudIoTest, ReadsAsciiPlyAndRefusesBigEndian) {
  std::ofstream(Path("a.ply")) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                  "property float z\nend_header\n1 2 3\n";
  const auto cloud = ReadPly(Path("a.ply"));
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  ASSERT_EQ(cloud->size(), 1u);
  EXPECT_EQ(cloud->positions[0], Eigen::Vector3f(1, 2, 3));
  std::ofstream(Path("b.ply")) << "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\n"
                                  "property float y\nproperty float z\nend_header\n123456789012";
  const Status big = ReadPly(Path("b.ply")).status();
  EXPECT_EQ(big.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(big.message().find("format"), std::string::npos) << big.message();
}

TEST_F(CloudIoTest, ReadToleratesOtherOrderTypesAndTrailingFaces) {
  std::string data =
      "ply\nformat binary_little_endian 1.0\ncomment made elsewhere\nelement vertex 2\n"
      "property uchar pixel\nproperty double z\nproperty float x\nproperty float y\nproperty int instance_id\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const auto put = [&](const auto& v) { data.append(reinterpret_cast<const char*>(&v), sizeof(v)); };
  for (int i = 0; i < 2; ++i) {
    put(static_cast<uint8_t>(10 + i));
    put(static_cast<double>(3.5 + i));
    put(static_cast<float>(1 + i));
    put(static_cast<float>(2 + i));
    put(static_cast<int32_t>(7 * i));
    put(0.0f);
    put(0.0f);
    put(1.0f);
  }
  put(static_cast<uint8_t>(3));
  for (int k = 0; k < 3; ++k) put(static_cast<int32_t>(k));
  std::ofstream(Path("o.ply"), std::ios::binary) << data;

  const auto cloud = ReadPly(Path("o.ply"));
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  EXPECT_EQ(cloud->fields, kFieldPosition | kFieldNormal | kFieldInstanceId | kFieldPixel);
  ASSERT_EQ(cloud->size(), 2u);
  EXPECT_EQ(cloud->positions[1], Eigen::Vector3f(2, 3, 4.5f));
  EXPECT_EQ(cloud->normals[0], Eigen::Vector3f(0, 0, 1));
  EXPECT_EQ(cloud->instance_ids[1], 7u);
  EXPECT_EQ(cloud->pixels[1], 11u);
}

// A PCD written elsewhere: other field order, sizes and signedness, a COUNT 3 field, CRLF lines.
TEST_F(CloudIoTest, PcdReadToleratesOtherOrderTypesAndCounts) {
  std::string data =
      "# .PCD v0.7 - Point Cloud Data file format\r\nVERSION 0.7\r\n"
      "FIELDS status z x y instance rgb normal_x normal_y normal_z\r\n"
      "SIZE 2 8 4 4 8 4 4 4 4\r\nTYPE U F F F I U F F F\r\nCOUNT 1 1 1 1 1 3 1 1 1\r\n"
      "WIDTH 2\r\nHEIGHT 1\r\nVIEWPOINT 0 0 0 1 0 0 0\r\nPOINTS 2\r\nDATA binary\r\n";
  const auto put = [&](const auto& v) { data.append(reinterpret_cast<const char*>(&v), sizeof(v)); };
  for (int i = 0; i < 2; ++i) {
    put(static_cast<uint16_t>(2 + i));
    put(static_cast<double>(3.5 + i));
    put(static_cast<float>(1 + i));
    put(static_cast<float>(2 + i));
    put(static_cast<int64_t>(7 * i));
    for (int k = 0; k < 3; ++k) put(static_cast<uint32_t>(0xFFFFFFu));
    put(0.0f);
    put(1.0f);
    put(0.0f);
  }
  std::ofstream(Path("o.pcd"), std::ios::binary) << data;

  const auto cloud = ReadPcd(Path("o.pcd"));
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  EXPECT_EQ(cloud->fields, kFieldPosition | kFieldNormal | kFieldInstanceId | kFieldStatus);
  ASSERT_EQ(cloud->size(), 2u);
  EXPECT_EQ(cloud->positions[1], Eigen::Vector3f(2, 3, 4.5f));
  EXPECT_EQ(cloud->normals[0], Eigen::Vector3f(0, 1, 0));
  EXPECT_EQ(cloud->instance_ids[1], 7u);
  EXPECT_EQ(cloud->statuses[1], static_cast<uint8_t>(PointStatus::kFlyingPixel));
}

TEST_F(CloudIoTest, PcdReadRejectsWhatItCannotRead) {
  const std::string head = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nPOINTS 1\n";
  const auto read = [&](const std::string& text) {
    std::ofstream(Path("r.pcd"), std::ios::binary) << text << std::string(12, '\0');
    return ReadPcd(Path("r.pcd")).status();
  };
  EXPECT_TRUE(read(head + "DATA binary\n").ok());
  // Twelve NUL bytes are neither numbers nor an LZF stream of 12 bytes.
  EXPECT_EQ(read(head + "DATA ascii\n").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(read(head + "DATA binary_compressed\n").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(read(head + "DATA binary_packed\n").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(read(head).code(), StatusCode::kInvalidArgument);  // no DATA line
  EXPECT_EQ(read("FIELDS x y\nSIZE 4 4\nTYPE F F\nPOINTS 1\nDATA binary\n").code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(read("FIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nPOINTS 1\nDATA binary\n").code(),
            StatusCode::kInvalidArgument);  // 2-byte float
  EXPECT_EQ(read("FIELDS x y z\nSIZE 4 4\n").code(), StatusCode::kInvalidArgument);  // too few sizes
}

// COUNT -1 reads as SIZE_MAX through an unsigned stream; its stride wrapped and the reader decoded
// past each record (found by cloud_upload_fuzzer).
TEST(PcdCount, AWrappingCountIsRefusedBeforeAnyRecordIsRead) {
  const std::string head = "VERSION 0.7\nFIELDS x y z status range\nSIZE 4 4 4 2 2\nTYPE F F F U I\n";
  const std::string tail = "POINTS 2\nDATA binary\n" + std::string(64, '\0');
  for (const char* count : {"1 1 1 -1 1", "1 1 1 1 18446744073709551615", "1 1 1 1 65537"}) {
    const auto cloud = ParsePcd(head + "COUNT " + count + "\n" + tail, "upload", UINT64_MAX);
    EXPECT_EQ(cloud.status().code(), StatusCode::kInvalidArgument) << count;
  }
  const auto fine = ParsePcd(head + "COUNT 1 1 1 1 1\n" + tail, "upload", UINT64_MAX);
  ASSERT_TRUE(fine.ok()) << fine.status().ToString();
  EXPECT_EQ(fine->size(), 2u);
}


TEST_F(CloudIoTest, EncodePlyWritesWhatWritePlyWrites) {
  for (const size_t n : {size_t{0}, size_t{3}, size_t{40000}}) {
    const PointCloud cloud = MakeCloud(kEveryField, n);
    ASSERT_TRUE(WritePly(cloud, Path("w.ply")).ok());
    const auto bytes = EncodePly(cloud);
    ASSERT_TRUE(bytes.ok()) << bytes.status().ToString();
    EXPECT_EQ(*bytes, ReadAll(Path("w.ply"))) << n << " points";
  }
  PointCloud inconsistent = MakeCloud(kFieldsDefault, 3);
  inconsistent.normals.pop_back();
  EXPECT_EQ(EncodePly(inconsistent).status().code(), StatusCode::kInvalidArgument);
}

TEST_F(CloudIoTest, BytesInMemoryReadAsTheFilesDo) {
  const PointCloud cloud = MakeCloud(kEveryField, 40000);
  ASSERT_TRUE(WritePly(cloud, Path("m.ply")).ok());
  ASSERT_TRUE(WritePcd(cloud, Path("m.pcd")).ok());
  const auto ply = ParsePly(ReadAll(Path("m.ply")), "upload", UINT64_MAX);
  ASSERT_TRUE(ply.ok()) << ply.status().ToString();
  ExpectSameCloud(cloud, *ply);
  const auto pcd = ParsePcd(ReadAll(Path("m.pcd")), "upload", UINT64_MAX);
  ASSERT_TRUE(pcd.ok()) << pcd.status().ToString();
  ExpectSameCloud(cloud, *pcd);
}

TEST_F(CloudIoTest, BytesInMemoryNameWhereTheyCameFromWhenRefused) {
  const PointCloud cloud = MakeCloud(kFieldsDefault, 10);
  ASSERT_TRUE(WritePly(cloud, Path("b.ply")).ok());
  ASSERT_TRUE(WritePcd(cloud, Path("b.pcd")).ok());
  const std::string ply = ReadAll(Path("b.ply"));
  const std::string pcd = ReadAll(Path("b.pcd"));

  const Status not_ply = ParsePly(pcd, "cloud data", UINT64_MAX).status();
  EXPECT_EQ(not_ply.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(not_ply.message(), "cloud data: not a PLY file");
  EXPECT_EQ(ParsePcd("FIELDS x y\nDATA binary\n", "cloud data", UINT64_MAX).status().code(),
            StatusCode::kInvalidArgument);
  for (const auto& [bytes, parse] : {std::pair{ply, &ParsePly}, std::pair{pcd, &ParsePcd}}) {
    const std::string_view cut = std::string_view(bytes).substr(0, bytes.size() - 5);
    const Status truncated = parse(cut, "cloud data", UINT64_MAX).status();
    EXPECT_EQ(truncated.code(), StatusCode::kDataLoss) << truncated.ToString();
    EXPECT_TRUE(truncated.message().starts_with("cloud data: ")) << truncated.message();
    // Ten points of the default fields take 10 x 36 bytes as arrays.
    EXPECT_TRUE(parse(bytes, "cloud data", 360).ok());
    const Status too_big = parse(bytes, "cloud data", 359).status();
    EXPECT_EQ(too_big.code(), StatusCode::kResourceExhausted) << too_big.ToString();
    EXPECT_TRUE(too_big.message().starts_with("cloud data: 10 points of 36 bytes")) << too_big.message();
  }
  EXPECT_EQ(ParsePly("", "cloud data", UINT64_MAX).status().code(), StatusCode::kInvalidArgument);
}

TEST_F(CloudIoTest, AHeaderThatPromisesBillionsOfPointsIsRefusedBeforeAllocating) {
  const std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty char x\n"
                          "property char y\nproperty char z\nend_header\nabc";
  EXPECT_EQ(ParsePly(ply, "cloud data", 1 << 20).status().code(), StatusCode::kDataLoss);
  const std::string pcd = "FIELDS x y z\nSIZE 1 1 1\nTYPE I I I\nCOUNT 1 1 1\nPOINTS 4000000000\nDATA binary\nabc";
  EXPECT_EQ(ParsePcd(pcd, "cloud data", 1 << 20).status().code(), StatusCode::kDataLoss);
}

// Text as an ASCII PLY or PCD holds it: every value of a record, %.9g floats (exact for float32).
std::string AsciiRecords(const PointCloud& c) {
  std::string text;
  char buf[64];
  const auto put = [&](double v, bool integer) {
    std::snprintf(buf, sizeof(buf), integer ? "%.0f " : "%.9g ", v);
    text += buf;
  };
  for (size_t i = 0; i < c.size(); ++i) {
    for (int k = 0; k < 3; ++k) put(c.positions[i][k], false);
    if (c.Has(kFieldNormal)) for (int k = 0; k < 3; ++k) put(c.normals[i][k], false);
    if (c.Has(kFieldRange)) put(c.ranges[i], false);
    if (c.Has(kFieldIntensity)) put(c.intensities[i], false);
    if (c.Has(kFieldInstanceId)) put(c.instance_ids[i], true);
    if (c.Has(kFieldPixel)) put(c.pixels[i], true);
    if (c.Has(kFieldCleanPosition)) for (int k = 0; k < 3; ++k) put(c.clean_positions[i][k], false);
    if (c.Has(kFieldIncidence)) put(c.incidence_angles[i], false);
    if (c.Has(kFieldStatus)) put(c.statuses[i], true);
    if (c.Has(kFieldEstimatedNormal)) for (int k = 0; k < 3; ++k) put(c.estimated_normals[i][k], false);
    text.back() = '\n';
  }
  return text;
}

constexpr const char* kEveryPlyProperty =
    "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
    "property float range\nproperty float intensity\nproperty uint instance\nproperty uint pixel\n"
    "property float clean_x\nproperty float clean_y\nproperty float clean_z\nproperty float incidence\n"
    "property uchar status\nproperty float enx\nproperty float eny\nproperty float enz\n";
constexpr const char* kEveryPcdField =
    "FIELDS x y z normal_x normal_y normal_z range intensity instance pixel clean_x clean_y clean_z incidence status "
    "est_normal_x est_normal_y est_normal_z\nSIZE 4 4 4 4 4 4 4 4 4 4 4 4 4 4 1 4 4 4\n"
    "TYPE F F F F F F F F U U F F F F U F F F\nCOUNT 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1\n";

TEST_F(CloudIoTest, AsciiPlyAndPcdKeepEveryField) {
  // More points than one decode block; ids and pixels up to the top of uint32.
  const PointCloud cloud = MakeCloud(kEveryField, 20000);
  const std::string records = AsciiRecords(cloud);
  const std::string ply = "ply\r\nformat ascii 1.0\r\ncomment CRLF header\r\nelement vertex 20000\r\n" +
                          std::string(kEveryPlyProperty) + "element camera 1\nproperty float view_px\nend_header\n" +
                          records + "0.5\n";
  const std::string pcd = "# .PCD v0.7\nVERSION 0.7\n" + std::string(kEveryPcdField) +
                          "WIDTH 20000\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 20000\nDATA ascii\n" + records;
  const auto from_ply = ParsePly(ply, "upload", UINT64_MAX);
  ASSERT_TRUE(from_ply.ok()) << from_ply.status().ToString();
  ExpectSameCloud(cloud, *from_ply);
  const auto from_pcd = ParsePcd(pcd, "upload", UINT64_MAX);
  ASSERT_TRUE(from_pcd.ok()) << from_pcd.status().ToString();
  ExpectSameCloud(cloud, *from_pcd);
  // The same files from disk.
  std::ofstream(Path("a.ply"), std::ios::binary) << ply;
  std::ofstream(Path("a.pcd"), std::ios::binary) << pcd;
  const auto file_ply = ReadCloud(Path("a.ply"));
  const auto file_pcd = ReadCloud(Path("a.pcd"));
  ASSERT_TRUE(file_ply.ok() && file_pcd.ok());
  ExpectSameCloud(cloud, *file_ply);
  ExpectSameCloud(cloud, *file_pcd);
}

TEST_F(CloudIoTest, AsciiReadsNanSignsExponentsAndSkipsElementsBeforeTheVertices) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement camera 2\nproperty float a\nproperty int b\nelement vertex 3\n"
      "property double x\nproperty float y\nproperty float z\nproperty short instance\nend_header\n"
      "1 2\n3 4\n+1.5 -2e-3 3E2 7\nnan nan nan 0\n-inf 0.0 1 32767\n";
  const auto cloud = ParsePly(ply, "upload", UINT64_MAX);
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  ASSERT_EQ(cloud->size(), 3u);
  EXPECT_EQ(cloud->positions[0], Eigen::Vector3f(1.5f, -0.002f, 300.0f));
  EXPECT_TRUE(cloud->positions[1].array().isNaN().all());
  EXPECT_EQ(cloud->positions[2].x(), -std::numeric_limits<float>::infinity());
  EXPECT_EQ(cloud->instance_ids, (std::vector<uint32_t>{7, 0, 32767}));
  // COUNT 2 fields take two values, the first is read.
  const std::string pcd = "FIELDS x y z range\nSIZE 4 4 4 8\nTYPE F F F F\nCOUNT 1 1 1 2\nPOINTS 2\nDATA ascii\n"
                          "1 2 3 4.5 9\n5 6 7 8.5 9\n";
  const auto counted = ParsePcd(pcd, "upload", UINT64_MAX);
  ASSERT_TRUE(counted.ok()) << counted.status().ToString();
  EXPECT_EQ(counted->positions[1], Eigen::Vector3f(5, 6, 7));
  EXPECT_EQ(counted->ranges, (std::vector<float>{4.5f, 8.5f}));
}

TEST_F(CloudIoTest, HostileAsciiIsRefusedNamingWhereItWentWrong) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nproperty uchar status\nend_header\n";
  const auto parse = [](const std::string& bytes) { return ParsePly(bytes, "cloud data", 1 << 20).status(); };
  // A count that lies: three vertices declared, two given.
  const Status short_count = parse(head + "1 2 3 1\n4 5 6 1\n");
  EXPECT_EQ(short_count.code(), StatusCode::kDataLoss);
  EXPECT_NE(short_count.message().find("truncated"), std::string::npos) << short_count.message();
  // Room for the values but one is missing at the end.
  const Status cut = parse(head + "1 2 3 1\n4 5 6 1\n7 8 9      \n");
  EXPECT_EQ(cut.code(), StatusCode::kDataLoss);
  EXPECT_NE(cut.message().find("vertex 2, property 'status'"), std::string::npos) << cut.message();
  const Status word = parse(head + "1 2 3 1\n4 five 6 1\n7 8 9 1\n");
  EXPECT_EQ(word.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(word.message(), "cloud data: vertex 1, property 'y': 'five' is not a number");
  const Status too_big = parse(head + "1 2 3 1\n4 5 6 256\n7 8 9 1\n");
  EXPECT_EQ(too_big.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(too_big.message().find("property 'status': 256 does not fit"), std::string::npos) << too_big.message();
  EXPECT_EQ(parse(head + "1 2 3 1\n4 5 6 1.5\n7 8 9 1\n").code(), StatusCode::kInvalidArgument);
  // Billions of points declared over a few bytes: refused before anything is allocated.
  const std::string huge = "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                           "property float z\nend_header\n1 2 3\n";
  EXPECT_EQ(ParsePly(huge, "cloud data", UINT64_MAX).status().code(), StatusCode::kDataLoss);
  // Elements before the vertices whose value counts add up past 2^64.
  const std::string wrapping = "ply\nformat ascii 1.0\nelement a 9223372036854775807\nproperty float v\n"
                               "element b 9223372036854775807\nproperty float v\nelement c 2\nproperty float v\n"
                               "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                               "end_header\n1 2 3\n";
  EXPECT_EQ(ParsePly(wrapping, "cloud data", UINT64_MAX).status().code(), StatusCode::kInvalidArgument);
  const std::string pcd = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nPOINTS 18446744073709551615\n"
                          "DATA ascii\n1 2 3\n";
  EXPECT_EQ(ParsePcd(pcd, "cloud data", UINT64_MAX).status().code(), StatusCode::kDataLoss);
}

// LZF of literal runs only (a valid stream any LZF decoder reads), field by field as PCD stores it.
std::string LiteralLzf(const std::string& raw) {
  std::string out;
  for (size_t at = 0; at < raw.size(); at += 32) {
    const size_t n = std::min<size_t>(32, raw.size() - at);
    out += static_cast<char>(n - 1);
    out += raw.substr(at, n);
  }
  return out;
}

std::string CompressedPcd(const std::string& fields, uint32_t points, const std::string& lzf, uint32_t raw_size) {
  std::string pcd = fields + "WIDTH " + std::to_string(points) + "\nHEIGHT 1\nPOINTS " + std::to_string(points) +
                    "\nDATA binary_compressed\n";
  const uint32_t sizes[2] = {static_cast<uint32_t>(lzf.size()), raw_size};
  pcd.append(reinterpret_cast<const char*>(sizes), 8);
  return pcd + lzf;
}

TEST_F(CloudIoTest, BinaryCompressedPcdKeepsEveryField) {
  const PointCloud cloud = MakeCloud(kEveryField, 20000);
  ASSERT_TRUE(WritePcd(cloud, Path("c.pcd")).ok());
  // The binary body transposed to one column per field.
  const std::string file = ReadAll(Path("c.pcd"));
  const std::string body = file.substr(file.find("DATA binary\n") + 12);
  const size_t n = cloud.size(), stride = body.size() / n;
  const std::vector<size_t> sizes = {4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 1, 4, 4, 4};
  std::string columns;
  for (size_t f = 0, offset = 0; f < sizes.size(); offset += sizes[f++]) {
    for (size_t i = 0; i < n; ++i) columns += body.substr(i * stride + offset, sizes[f]);
  }
  ASSERT_EQ(columns.size(), body.size());
  const auto back = ParsePcd(CompressedPcd(kEveryPcdField, 20000, LiteralLzf(columns), columns.size()), "upload",
                             UINT64_MAX);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ExpectSameCloud(cloud, *back);
}

TEST_F(CloudIoTest, LzfBackReferencesExpandAndHostileStreamsAreRefused) {
  const std::string fields = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
  // Two points of zeros: one literal zero byte, then a back-reference of 23 bytes at distance 1
  // (ctrl 7 << 5 with 23 - 9 = 14 in the extra byte).
  const std::string zeros = std::string(1, '\0') + std::string(1, '\0') + static_cast<char>(0xE0) + '\x0e' + '\0';
  const auto two = ParsePcd(CompressedPcd(fields, 2, zeros, 24), "cloud data", UINT64_MAX);
  ASSERT_TRUE(two.ok()) << two.status().ToString();
  EXPECT_EQ(two->positions, (std::vector<Eigen::Vector3f>(2, Eigen::Vector3f::Zero())));

  const auto parse = [&](uint32_t points, const std::string& lzf, uint32_t raw) {
    return ParsePcd(CompressedPcd(fields, points, lzf, raw), "cloud data", 1 << 20).status();
  };
  // A reference before the start of the output.
  EXPECT_EQ(parse(2, std::string(1, '\0') + '\0' + static_cast<char>(0xE0) + '\x0e' + '\x05', 24).code(),
            StatusCode::kDataLoss);
  // Sizes that lie: against POINTS, against what LZF can expand to, against the bytes there.
  const Status points = parse(3, zeros, 24);
  EXPECT_EQ(points.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(points.message().find("POINTS 3"), std::string::npos) << points.message();
  const Status ratio = parse(100000000, zeros, 1200000000);
  EXPECT_EQ(ratio.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(ratio.message().find("more than LZF can expand to"), std::string::npos) << ratio.message();
  std::string lying = CompressedPcd(fields, 2, zeros, 24);
  lying[lying.size() - zeros.size() - 8] = 100;  // compressed size 100, 5 bytes follow
  EXPECT_EQ(ParsePcd(lying, "cloud data", 1 << 20).status().code(), StatusCode::kDataLoss);
  EXPECT_EQ(ParsePcd(fields + "POINTS 1\nDATA binary_compressed\n\x01\x02", "cloud data", 1 << 20).status().code(),
            StatusCode::kDataLoss);
  // A stream that ends short of its declared size.
  EXPECT_EQ(parse(2, LiteralLzf(std::string(20, 'a')), 24).code(), StatusCode::kDataLoss);
  // Within every bound but the caller's limit on the arrays.
  EXPECT_EQ(ParsePcd(CompressedPcd(fields, 2, zeros, 24), "cloud data", 23).status().code(),
            StatusCode::kResourceExhausted);
}

// A DATA line that runs to the end of the bytes (its data after a vertical tab, which the header's
// word split takes as a space) left the readers at position -1 (found by cloud_upload_fuzzer).
TEST(CloudHeaderAtTheEnd, AHeaderWithoutItsLastNewlineIsTruncatedNotAThrow) {
  const std::string fields = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nPOINTS 1\n";
  for (const char* data : {"DATA ascii\v1 2 3", "DATA binary_compressed\v12345678", "DATA binary"}) {
    const Status status = ParsePcd(fields + data, "cloud data", 1 << 20).status();
    EXPECT_EQ(status.code(), StatusCode::kDataLoss) << data;
  }
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                          "property float z\nend_header";
  EXPECT_EQ(ParsePly(ply, "cloud data", 1 << 20).status().code(), StatusCode::kDataLoss);
}

}  // namespace
}  // namespace vscan

namespace vscan {
namespace {

// A header of NUL bytes or non-ASCII text is quoted as \xNN escapes, cut short: no raw bytes reach
// the client's message.
TEST(CloudHeaderQuotes, UntrustedBytesAreEscapedAndCut) {
  const Status nul = ParsePly("ply\nformat binary_little_endian 1.0\n" + std::string(120, '\0'), "cloud data", 1 << 20)
                         .status();
  EXPECT_EQ(nul.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(nul.message().find('\0'), std::string::npos);
  EXPECT_NE(nul.message().find("\\x00\\x00"), std::string::npos) << nul.message();
  EXPECT_LT(nul.message().size(), 320u) << nul.message();
  const Status accented = ParsePly("ply\nformat ascii 1.0\nelement vertex 1\n\xc3\xa9t\xc3\xa9\n", "cloud data", 1 << 20)
                              .status();
  EXPECT_NE(accented.message().find("\\xc3\\xa9t\\xc3\\xa9"), std::string::npos) << accented.message();
  EXPECT_EQ(TextExcerpt("abc\ndef", 5), "abc\\x0ad...");
}

}  // namespace
}  // namespace vscan
