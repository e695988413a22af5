#include "geometry/import_protocol.h"

#include <gtest/gtest.h>

#include <string>

namespace vscan::geometry {
namespace {

std::string Joined(const StatusOr<TriangleMesh>& result) {
  const EncodedImportResult encoded = EncodeImportResult(result);
  return encoded.header + encoded.payload;
}

TEST(ImportProtocolTest, AMeshComesBackAsTheHelperSentIt) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  const std::string bytes = Joined(mesh);
  EXPECT_EQ(bytes.size(), kImportResultHeaderSize + EncodeMesh(mesh).size());
  const auto received = ParseImportResult(bytes);
  ASSERT_TRUE(received.ok()) << received.status().ToString();
  EXPECT_EQ(received->vertices, mesh.vertices);
  EXPECT_EQ(received->triangles, mesh.triangles);
}

TEST(ImportProtocolTest, AnErrorKeepsItsCodeAndMessage) {
  const Status refused = InvalidArgument("mesh data", "not a PLY, OBJ or STL file");
  const auto received = ParseImportResult(Joined(refused));
  EXPECT_EQ(received.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(received.status().message(), refused.message());
}

TEST(ImportProtocolTest, DamagedResultsAreInternal) {
  const std::string bytes = Joined(ResourceExhausted("too many triangles"));
  EXPECT_EQ(ParseImportResult(bytes.substr(0, bytes.size() - 1)).status().code(), StatusCode::kInternal);
  EXPECT_EQ(ParseImportResult(bytes + "x").status().code(), StatusCode::kInternal);
  EXPECT_EQ(ParseImportResult("VSIX" + bytes.substr(4)).status().code(), StatusCode::kInternal);
  // An OK header whose payload is no mesh.
  EXPECT_EQ(ParseImportResult(ImportResultHeader(StatusCode::kOk, 3) + "abc").status().code(),
            StatusCode::kInternal);
  // A code the helper never sends.
  EXPECT_EQ(ParseImportResult(ImportResultHeader(static_cast<StatusCode>(7), 0)).status().code(),
            StatusCode::kInternal);
}

}  // namespace
}  // namespace vscan::geometry
