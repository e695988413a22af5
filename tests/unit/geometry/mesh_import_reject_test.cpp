// Hostile and broken input: every case must come back as a clean error and never touch the disk.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <thread>

#include "geometry/mesh_import.h"

namespace vscan::geometry {
namespace {

constexpr MeshFileFormat kAllFormats[] = {MeshFileFormat::kAuto, MeshFileFormat::kPly, MeshFileFormat::kObj,
                                          MeshFileFormat::kStl};

constexpr char kRejectTrianglePly[] =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

void ExpectInvalidMesh(const StatusOr<TriangleMesh>& result, const std::string& prefix) {
  ASSERT_FALSE(result.ok()) << "accepted a mesh with " << result->triangles.size() << " triangles";
  EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument) << result.status().ToString();
  EXPECT_EQ(result.status().message().rfind(prefix, 0), 0u) << result.status().message();
  EXPECT_EQ(result.status().message().find("$$$"), std::string::npos) << result.status().message();
}

std::string BinaryStl(const std::vector<std::array<float, 9>>& facets) {
  std::string bytes(80, ' ');
  auto count = static_cast<uint32_t>(facets.size());
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& f : facets) {
    bytes.append(12, '\0');
    bytes.append(reinterpret_cast<const char*>(f.data()), 36);
    bytes.append(2, '\0');
  }
  return bytes;
}

TEST(MeshImportRejectTest, BadScale) {
  for (double scale : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    ExpectInvalidMesh(ImportMesh(kRejectTrianglePly, MeshFileFormat::kPly, scale), "scale: ");
  }
  EXPECT_TRUE(ImportMesh(kRejectTrianglePly, MeshFileFormat::kPly, 1e-6).ok());
}

TEST(MeshImportRejectTest, VerticesBeyondTenKilometresOnceScaled) {
  const std::string huge = BinaryStl({{1e38f, 0, 0, 0, 1, 0, 0, 0, 1}});
  ExpectInvalidMesh(ImportMesh(huge, MeshFileFormat::kStl, 1.0), "mesh data: a vertex lies beyond 10 km");
  // 2 m in kilometres is 2 km: in bounds; 20 km is not.
  const std::string two = BinaryStl({{2, 0, 0, 0, 1, 0, 0, 0, 1}});
  EXPECT_TRUE(ImportMesh(two, MeshFileFormat::kStl, 1000.0).ok());
  ExpectInvalidMesh(ImportMesh(two, MeshFileFormat::kStl, 10000.0), "mesh data: a vertex lies beyond 10 km");
}

TEST(MeshImportRejectTest, EmptyBytes) {
  for (auto format : kAllFormats) ExpectInvalidMesh(ImportMesh("", format, 1.0), "mesh data: empty");
}

TEST(MeshImportRejectTest, GarbageBytes) {
  std::mt19937 rng(1234);
  for (int round = 0; round < 8; ++round) {
    std::string garbage(200 + 333 * round, '\0');
    for (auto& c : garbage) c = static_cast<char>(rng() & 0xff);
    for (auto format : kAllFormats) ExpectInvalidMesh(ImportMesh(garbage, format, 1.0), "mesh data: ");
  }
  ExpectInvalidMesh(ImportMesh("this is not a mesh\n", MeshFileFormat::kAuto, 1.0), "mesh data: ");
}

TEST(MeshImportRejectTest, PlyWithoutFaces) {
  constexpr char kPoints[] =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n";
  ExpectInvalidMesh(ImportMesh(kPoints, MeshFileFormat::kAuto, 1.0), "mesh data: ");
}

TEST(MeshImportRejectTest, LinesAndPointsOnlyHaveNoTriangles) {
  ExpectInvalidMesh(ImportMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n", MeshFileFormat::kObj, 1.0), "mesh data: ");
}

TEST(MeshImportRejectTest, NonFiniteVertices) {
  for (const char* bad : {"nan", "inf", "-inf"}) {
    std::string ply = kRejectTrianglePly;
    ply.replace(ply.find("1 0 0\n"), 1, bad);
    ExpectInvalidMesh(ImportMesh(ply, MeshFileFormat::kPly, 1.0), "mesh data: ");
  }
  float nan = std::numeric_limits<float>::quiet_NaN();
  ExpectInvalidMesh(ImportMesh(BinaryStl({{0, 0, 0, 1, 0, 0, 0, nan, 0}}), MeshFileFormat::kStl, 1.0), "mesh data: ");
  ExpectInvalidMesh(ImportMesh(BinaryStl({{0, 0, 0, 1, 0, 0, 0, nan, 0}}), MeshFileFormat::kAuto, 1.0), "mesh data: ");
  EXPECT_TRUE(ImportMesh(BinaryStl({{0, 0, 0, 1, 0, 0, 0, 1, 0}}), MeshFileFormat::kAuto, 1.0).ok());
}

TEST(MeshImportRejectTest, CoordinatesThatOverflowFloatAfterScaling) {
  std::string ply = kRejectTrianglePly;
  ply.replace(ply.find("1 0 0\n"), 1, "3e38");
  ExpectInvalidMesh(ImportMesh(ply, MeshFileFormat::kPly, 1.0), "mesh data: ");
  ExpectInvalidMesh(ImportMesh(ply, MeshFileFormat::kPly, 10.0), "mesh data: ");
}

TEST(MeshImportRejectTest, FaceIndexOutOfRange) {
  // Without validation before post-processing, this PLY crashes assimp 5.2.
  std::string ply = kRejectTrianglePly;
  ply.replace(ply.find("3 0 1 2"), 7, "3 0 1 100000");
  ExpectInvalidMesh(ImportMesh(ply, MeshFileFormat::kPly, 1.0), "mesh data: ");
  ExpectInvalidMesh(ImportMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 100000\n", MeshFileFormat::kObj, 1.0), "mesh data: ");
}

TEST(MeshImportRejectTest, MalformedPlyHeadersFailFast) {
  // Found by fuzzing: assimp's PLY loader hangs or reads out of bounds on these, so they must be
  // turned away before it sees them.
  std::string no_end = kRejectTrianglePly;
  no_end.replace(no_end.find("end_header"), 10, std::string("e\0\0_header", 10));
  ExpectInvalidMesh(ImportMesh(no_end, MeshFileFormat::kAuto, 1.0), "mesh data: PLY header");
  std::string bad_keyword = kRejectTrianglePly;
  bad_keyword.replace(bad_keyword.find("element vertex"), 14, "elem tnveertex");
  ExpectInvalidMesh(ImportMesh(bad_keyword, MeshFileFormat::kPly, 1.0), "mesh data: PLY header");
  std::string huge_count = kRejectTrianglePly;
  huge_count.replace(huge_count.find("element vertex 3"), 16, "element vertex 4000000000");
  ExpectInvalidMesh(ImportMesh(huge_count, MeshFileFormat::kPly, 1.0), "mesh data: PLY header");
}

TEST(MeshImportRejectTest, FaceWithoutVertices) {
  // A face list of length zero trips an assertion inside assimp's triangulation.
  std::string ply = kRejectTrianglePly;
  ply.replace(ply.find("3 0 1 2"), 7, "0");
  ExpectInvalidMesh(ImportMesh(ply, MeshFileFormat::kPly, 1.0), "mesh data: ");
}

TEST(MeshImportRejectTest, TruncatedFiles) {
  std::string stl = BinaryStl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 1, 1, 0, 1, 0, 1, 1}});
  ExpectInvalidMesh(ImportMesh(stl.substr(0, stl.size() - 10), MeshFileFormat::kStl, 1.0), "mesh data: ");
  std::string ply = kRejectTrianglePly;
  ExpectInvalidMesh(ImportMesh(ply.substr(0, ply.size() - 10), MeshFileFormat::kPly, 1.0), "mesh data: ");
}

// An OBJ's mtllib names a path chosen by the uploader; the importer must not open it. A FIFO shows
// any attempt: opening it for reading blocks until this test's watcher opens the writing end.
TEST(MeshImportRejectTest, ObjMaterialLibraryIsNeverOpened) {
  std::string fifo = (std::filesystem::temp_directory_path() / ("vscan-mtl-" + std::to_string(::getpid()))).string();
  ::unlink(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);

  std::atomic<bool> done{false};
  std::atomic<bool> opened{false};
  std::thread watcher([&] {
    while (!done) {
      int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);  // succeeds only while a reader is there
      if (fd >= 0) {
        opened = true;
        ::close(fd);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  std::string obj = "mtllib " + fifo + "\nusemtl steel\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  auto mesh = ImportMesh(obj, MeshFileFormat::kObj, 1.0);
  done = true;
  watcher.join();
  ::unlink(fifo.c_str());

  EXPECT_FALSE(opened) << "the importer opened the material library";
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_EQ(mesh->triangles.size(), 1u);
}

}  // namespace
}  // namespace vscan::geometry
