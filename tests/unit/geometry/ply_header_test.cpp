#include "geometry/ply_header.h"

#include <gtest/gtest.h>

#include <string>

namespace vscan::geometry {
namespace {

constexpr char kHeader[] =
    "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
constexpr char kBody[] = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

std::string With(std::string header, const std::string& from, const std::string& to) {
  header.replace(header.find(from), from.size(), to);
  return header + kBody;
}

void ExpectRejected(const std::string& bytes) {
  Status status = CheckPlyHeader(bytes);
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << bytes;
  EXPECT_EQ(status.message().rfind("mesh data: PLY header", 0), 0u) << status.message();
}

TEST(PlyHeaderTest, AcceptsWellFormedHeaders) {
  EXPECT_TRUE(CheckPlyHeader(std::string(kHeader) + kBody).ok());
  EXPECT_TRUE(CheckPlyHeader(With(kHeader, "\n", "\r\n")).ok());
  std::string binary = With(kHeader, "ascii", "binary_little_endian");
  binary.resize(binary.size() - sizeof(kBody) + 1);
  binary.append(3 * 12 + 1 + 3 * 4, '\0');
  EXPECT_TRUE(CheckPlyHeader(binary).ok());
}

// Each of these sent assimp 5.2's PLY loader into an endless loop or an out-of-bounds read.
TEST(PlyHeaderTest, RejectsMalformedHeaders) {
  ExpectRejected(With(kHeader, "end_header", std::string("e\0\0_header", 10)));
  ExpectRejected(With(kHeader, "end_header\n", ""));
  ExpectRejected(With(kHeader, "element vertex", "elem tnveertex"));
  ExpectRejected(With(kHeader, "format ascii 1.0", "format ascii 2.0"));
  ExpectRejected(With(kHeader, "format ascii 1.0", "format binary_little_endian 2.0"));
  ExpectRejected(With(kHeader, "format ascii 1.0", "format ascii \x01ply"));
  ExpectRejected(With(kHeader, "property float y", "properyt float y"));
  ExpectRejected(With(kHeader, "property float y", "property flaot y"));
  ExpectRejected(With(kHeader, "property list uchar int", "property list float int"));
  ExpectRejected(With(kHeader, "property list uchar int vertex_indices", "property list uchar ierty list uchar int"));
  ExpectRejected(With(kHeader, "element vertex 3\n", "property float w\nelement vertex 3\n"));
  ExpectRejected(With(kHeader, "ply\n", "ply \x80\n"));
  ExpectRejected(With(kHeader, "ply\n", "plyx\n"));
  ExpectRejected(std::string("ply\n") + std::string(70000, 'c') + "\n");
}

TEST(PlyHeaderTest, RejectsCountsTheFileCannotHold) {
  ExpectRejected(With(kHeader, "element vertex 3", "element vertex 4000000000"));
  ExpectRejected(With(kHeader, "element vertex 3", "element vertex 99999999999999999999"));
  ExpectRejected(With(kHeader, "element vertex 3", "element vertex -3"));
  ExpectRejected(With(kHeader, "element face 1", "element face 100"));
}

}  // namespace
}  // namespace vscan::geometry
