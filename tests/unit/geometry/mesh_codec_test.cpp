#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <limits>

#include "geometry/mesh_import.h"

namespace vscan::geometry {
namespace {

TriangleMesh SampleMesh() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1.5f, -2.25f, 1e-30f}, {-0.0f, std::numeric_limits<float>::max(), 3.14159f},
                   {std::numeric_limits<float>::denorm_min(), 7, -8}};
  mesh.triangles = {{0, 1, 2}, {3, 2, 1}, {0, 3, 1}};
  return mesh;
}

void ExpectBitIdentical(const TriangleMesh& a, const TriangleMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (size_t i = 0; i < a.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(std::bit_cast<uint32_t>(a.vertices[i][k]), std::bit_cast<uint32_t>(b.vertices[i][k]));
    }
  }
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(MeshCodecTest, RoundTripIsExact) {
  TriangleMesh mesh = SampleMesh();
  std::string bytes = EncodeMesh(mesh);
  EXPECT_EQ(bytes.size(), 24u + 12 * 4 + 12 * 3);
  auto decoded = DecodeMesh(bytes);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  ExpectBitIdentical(*decoded, mesh);
}

TEST(MeshCodecTest, EmptyMeshRoundTrips) {
  auto decoded = DecodeMesh(EncodeMesh(TriangleMesh{}));
  ASSERT_TRUE(decoded.ok());
  EXPECT_TRUE(decoded->vertices.empty());
  EXPECT_TRUE(decoded->triangles.empty());
}

TEST(MeshCodecTest, LayoutIsLittleEndian) {
  TriangleMesh mesh;
  mesh.vertices = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 1, 2}};
  std::string bytes = EncodeMesh(mesh);
  ASSERT_EQ(bytes.size(), 24u + 36 + 12);
  EXPECT_EQ(bytes.substr(0, 8), "VSMESH01");
  EXPECT_EQ(bytes.substr(8, 8), std::string("\x03\0\0\0\0\0\0\0", 8));
  EXPECT_EQ(bytes.substr(16, 8), std::string("\x01\0\0\0\0\0\0\0", 8));
  EXPECT_EQ(bytes.substr(24, 4), std::string("\0\0\x80\x3f", 4));  // 1.0f
  EXPECT_EQ(bytes.substr(24 + 36 + 8, 4), std::string("\x02\0\0\0", 4));
}

TEST(MeshCodecTest, EveryTruncationIsDataLoss) {
  std::string bytes = EncodeMesh(SampleMesh());
  for (size_t n = 0; n < bytes.size(); ++n) {
    auto decoded = DecodeMesh(std::string_view(bytes).substr(0, n));
    ASSERT_FALSE(decoded.ok()) << "accepted " << n << " bytes";
    EXPECT_EQ(decoded.status().code(), StatusCode::kDataLoss);
  }
  EXPECT_EQ(DecodeMesh(bytes + '\0').status().code(), StatusCode::kDataLoss);
}

TEST(MeshCodecTest, CorruptContentIsDataLoss) {
  std::string good = EncodeMesh(SampleMesh());

  std::string bad_magic = good;
  bad_magic[7] = '2';
  EXPECT_EQ(DecodeMesh(bad_magic).status().code(), StatusCode::kDataLoss);

  std::string bad_index = good;
  bad_index[24 + 48 + 4] = 4;  // second index of the first triangle -> 4, one past the last vertex
  EXPECT_EQ(DecodeMesh(bad_index).status().code(), StatusCode::kDataLoss);

  std::string huge_counts = good;
  for (int i = 8; i < 24; ++i) huge_counts[i] = '\xff';  // counts whose byte sizes overflow 64 bits
  EXPECT_EQ(DecodeMesh(huge_counts).status().code(), StatusCode::kDataLoss);

  std::string extra_vertex = good;
  extra_vertex[8] = 5;  // one vertex more than the bytes hold
  EXPECT_EQ(DecodeMesh(extra_vertex).status().code(), StatusCode::kDataLoss);

  std::string nan_vertex = good;
  float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan_vertex.data() + 24, &nan, 4);
  EXPECT_EQ(DecodeMesh(nan_vertex).status().code(), StatusCode::kDataLoss);
}

}  // namespace
}  // namespace vscan::geometry
