#include "reconstruction/poisson_process.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace vscan::reconstruction {
namespace {

// A Fibonacci sphere of radius 0.1 m with outward normals.
void Sphere(size_t n, std::vector<Eigen::Vector3f>& points, std::vector<Eigen::Vector3f>& normals) {
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (size_t i = 0; i < n; ++i) {
    const double y = 1.0 - 2.0 * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    const double r = std::sqrt(1.0 - y * y);
    const Eigen::Vector3f normal(static_cast<float>(r * std::cos(golden * i)), static_cast<float>(y),
                                 static_cast<float>(r * std::sin(golden * i)));
    normals.push_back(normal);
    points.push_back(0.1f * normal);
  }
}

TEST(PoissonInChild, SameMeshAsInProcess) {
  std::vector<Eigen::Vector3f> points, normals;
  Sphere(4000, points, normals);
  PoissonOptions options;
  options.depth = 6;
  // One thread: PCL's multi-threaded solve is compared only against itself run the same way.
  options.threads = 1;
  auto here = PoissonPcl(points, normals, options);
  // A bound far above the solve's needs changes nothing.
  auto child = PoissonInChild(VSCAN_POISSON_HELPER, points, normals, options, nullptr, uint64_t{1} << 30);
  ASSERT_TRUE(here.ok()) << here.status().ToString();
  ASSERT_TRUE(child.ok()) << child.status().ToString();
  ASSERT_FALSE(here->triangles.empty());
  EXPECT_EQ(EncodePoissonResult(*here), EncodePoissonResult(*child));
}

TEST(PoissonInChild, CancelKillsTheSolveAtOnce) {
  std::vector<Eigen::Vector3f> points, normals;
  Sphere(200000, points, normals);
  PoissonOptions options;
  options.depth = 10;
  std::atomic<bool> cancel{false};
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  auto mesh = PoissonInChild(VSCAN_POISSON_HELPER, points, normals, options, &cancel);
  stopper.join();
  EXPECT_EQ(mesh.status().code(), StatusCode::kCancelled);
}

TEST(PoissonInChild, AChildPastItsMemoryBoundEndsResourceExhausted) {
  std::vector<Eigen::Vector3f> points, normals;
  Sphere(20000, points, normals);
  PoissonOptions options;
  options.depth = 8;  // peaks near 160 MiB resident
  const auto start = std::chrono::steady_clock::now();
  auto mesh = PoissonInChild(VSCAN_POISSON_HELPER, points, normals, options, nullptr, uint64_t{32} << 20);
  EXPECT_EQ(mesh.status().code(), StatusCode::kResourceExhausted) << mesh.status().ToString();
  EXPECT_NE(mesh.status().message().find("poisson.depth"), std::string::npos) << mesh.status().message();
  EXPECT_NE(mesh.status().message().find("32 MiB"), std::string::npos) << mesh.status().message();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(PoissonFrames, RoundTripAndRejectTruncation) {
  std::vector<Eigen::Vector3f> points, normals;
  Sphere(10, points, normals);
  PoissonOptions options;
  options.depth = 7;
  options.threads = 3;
  const std::string bytes = EncodePoissonInput(points, normals, options);
  auto input = DecodePoissonInput(bytes);
  ASSERT_TRUE(input.ok());
  EXPECT_EQ(input->options.depth, 7);
  EXPECT_EQ(input->options.threads, 3);
  EXPECT_EQ(input->points, points);
  EXPECT_EQ(input->normals, normals);
  EXPECT_FALSE(DecodePoissonInput(bytes.substr(0, bytes.size() - 1)).ok());
  TriangleMesh mesh;
  mesh.vertices = points;
  mesh.triangles = {{0, 1, 2}, {9, 3, 4}};
  auto back = DecodePoissonResult(EncodePoissonResult(mesh));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->vertices, mesh.vertices);
  EXPECT_EQ(back->triangles, mesh.triangles);
  mesh.triangles = {{0, 1, 10}};
  EXPECT_FALSE(DecodePoissonResult(EncodePoissonResult(mesh)).ok());
}

TEST(EstimatePoissonBytes, GrowsWithDepthAndPointsAndStaysBelowMeasuredPeaks) {
  EXPECT_LT(EstimatePoissonBytes(1000, 8), EstimatePoissonBytes(1000, 9));
  EXPECT_LT(EstimatePoissonBytes(1000, 8), EstimatePoissonBytes(100000, 8));
  // Never above a peak measured with /usr/bin/time (KiB of resident memory, one thread): a refusal
  // on the estimate turns away only what could not have fitted.
  struct Measured {
    size_t points;
    int depth;
    uint64_t peak_kib;
  };
  for (const Measured& m : {Measured{2000, 6, 46212}, Measured{2000, 10, 103872}, Measured{20000, 10, 185936},
                            Measured{100000, 6, 61492}, Measured{100000, 8, 185560}, Measured{100000, 10, 351460}}) {
    EXPECT_LE(EstimatePoissonBytes(m.points, m.depth), m.peak_kib << 10) << m.points << " points, depth " << m.depth;
  }
}

}  // namespace
}  // namespace vscan::reconstruction
