// Imports in the vscan-mesh-import helper: same meshes as in process, clean errors when the helper
// fails, and no descriptors or children left behind.

#include "geometry/sandboxed_import.h"

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <string>
#include <filesystem>
#include <thread>
#include <vector>

#include "geometry/child_process.h"
#include "mesh_test_util.h"

namespace vscan::geometry {
namespace {

using namespace std::chrono_literals;

constexpr char kSandboxTrianglePly[] =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

ImportSandbox Sandbox(std::chrono::milliseconds timeout = 60s) {
  ImportSandbox sandbox;
  sandbox.helper_path = VSCAN_MESH_IMPORTER;
  sandbox.timeout = timeout;
  return sandbox;
}

size_t OpenDescriptors() {
  return static_cast<size_t>(std::distance(std::filesystem::directory_iterator("/proc/self/fd"),
                                           std::filesystem::directory_iterator()));
}

// Every child this process started has been reaped (none running, no zombie).
bool NoChildren() { return waitpid(-1, nullptr, WNOHANG) == -1 && errno == ECHILD; }

class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) { setenv(name, value, 1); }
  ~ScopedEnv() { unsetenv(name_); }

 private:
  const char* name_;
};

// A grid of w x h quads as a binary STL without any header text: 50 bytes per triangle.
std::string GridStl(uint32_t w, uint32_t h) {
  std::string bytes(80, '\0');
  const uint32_t count = 2 * w * h;
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  bytes.reserve(84 + 50 * size_t{count});
  auto facet = [&](std::array<float, 9> corners) {
    bytes.append(12, '\0');
    bytes.append(reinterpret_cast<const char*>(corners.data()), 36);
    bytes.append(2, '\0');
  };
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const float x0 = static_cast<float>(x), x1 = x0 + 1, y0 = static_cast<float>(y), y1 = y0 + 1;
      facet({x0, y0, 0, x1, y0, 0, x1, y1, 0});
      facet({x0, y0, 0, x1, y1, 0, x0, y1, 0});
    }
  }
  return bytes;
}

void ExpectSameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (size_t i = 0; i < a.vertices.size(); ++i) ASSERT_EQ(a.vertices[i], b.vertices[i]) << "vertex " << i;
  EXPECT_TRUE(a.triangles == b.triangles);
}

void ExpectInvalidSandboxed(const StatusOr<TriangleMesh>& result, const std::string& text) {
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument) << result.status().ToString();
  EXPECT_EQ(result.status().message().rfind("mesh data: ", 0), 0u) << result.status().message();
  EXPECT_NE(result.status().message().find(text), std::string::npos) << result.status().message();
}

class SandboxedImportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(NoChildren());
    fds_before_ = OpenDescriptors();
  }
  void TearDown() override {
    EXPECT_EQ(OpenDescriptors(), fds_before_) << "descriptors leaked";
    EXPECT_TRUE(NoChildren()) << "a child was left unreaped";
  }

 private:
  size_t fds_before_ = 0;
};

TEST_F(SandboxedImportTest, BunnyEqualsInProcessImport) {
  const std::string bytes = test::ReadDataFile("meshes/bunny/bunny_zipper_res2.ply");
  ASSERT_FALSE(bytes.empty());
  for (double metres_per_unit : {1.0, 0.001, 1.0 / 3.0}) {
    auto local = ImportMesh(bytes, MeshFileFormat::kAuto, metres_per_unit);
    auto isolated = ImportMeshIsolated(bytes, MeshFileFormat::kAuto, metres_per_unit, Sandbox());
    ASSERT_TRUE(local.ok()) << local.status().ToString();
    ASSERT_TRUE(isolated.ok()) << isolated.status().ToString();
    EXPECT_EQ(isolated->triangles.size(), 16301u);
    ExpectSameMesh(*local, *isolated);
  }
}

TEST_F(SandboxedImportTest, ErrorsComeBackAsImportMeshReportsThem) {
  for (auto [bytes, format] : {std::pair<std::string, MeshFileFormat>{"this is not a mesh\n", MeshFileFormat::kAuto},
                               {std::string(5000, '\xff'), MeshFileFormat::kStl},
                               {"ply\nformat ascii 1.0\nend_header\n", MeshFileFormat::kPly},
                               {"", MeshFileFormat::kObj}}) {
    auto local = ImportMesh(bytes, format, 1.0);
    auto isolated = ImportMeshIsolated(bytes, format, 1.0, Sandbox());
    ExpectInvalidSandboxed(isolated, "");
    ASSERT_FALSE(local.ok());
    EXPECT_EQ(isolated.status().message(), local.status().message());
  }
  auto bad_scale = ImportMeshIsolated(kSandboxTrianglePly, MeshFileFormat::kPly, -1.0, Sandbox());
  ASSERT_FALSE(bad_scale.ok());
  EXPECT_EQ(bad_scale.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(bad_scale.status().message().rfind("scale: ", 0), 0u) << bad_scale.status().message();
}

TEST_F(SandboxedImportTest, ImporterAbortIsReportedWithTheSignal) {
  ScopedEnv crash("VSCAN_MESH_IMPORT_TEST_CRASH", "abort");
  ExpectInvalidSandboxed(ImportMeshIsolated(kSandboxTrianglePly, MeshFileFormat::kPly, 1.0, Sandbox()),
                "could not be parsed (importer stopped by signal " + std::to_string(SIGABRT) + ")");
}

TEST_F(SandboxedImportTest, ImporterThatHangsIsKilledAtTheTimeout) {
  ScopedEnv hang("VSCAN_MESH_IMPORT_TEST_CRASH", "hang");
  const auto start = std::chrono::steady_clock::now();
  ExpectInvalidSandboxed(ImportMeshIsolated(kSandboxTrianglePly, MeshFileFormat::kPly, 1.0, Sandbox(500ms)),
                "import did not finish within 0.5 s");
  const auto elapsed = std::chrono::steady_clock::now() - start;
  EXPECT_GE(elapsed, 500ms);
  EXPECT_LT(elapsed, 5s);
}

TEST_F(SandboxedImportTest, HelperThatFailsOrPrintsNonsense) {
  ImportSandbox sandbox = Sandbox();
  sandbox.helper_path = "/bin/false";
  ExpectInvalidSandboxed(ImportMeshIsolated(kSandboxTrianglePly, MeshFileFormat::kPly, 1.0, sandbox),
                "importer exited with status 1");
  sandbox.helper_path = "/bin/echo";
  auto echoed = ImportMeshIsolated(kSandboxTrianglePly, MeshFileFormat::kPly, 1.0, sandbox);
  ASSERT_FALSE(echoed.ok());
  EXPECT_EQ(echoed.status().code(), StatusCode::kInternal) << echoed.status().ToString();
}

TEST_F(SandboxedImportTest, MissingHelperIsUnavailable) {
  for (const char* path : {"/nonexistent/vscan-mesh-import", "/", "/etc/hostname", ""}) {
    ImportSandbox sandbox = Sandbox();
    sandbox.helper_path = path;
    auto result = ImportMeshIsolated(kSandboxTrianglePly, MeshFileFormat::kPly, 1.0, sandbox);
    ASSERT_FALSE(result.ok()) << path;
    EXPECT_EQ(result.status().code(), StatusCode::kUnavailable) << result.status().ToString();
    EXPECT_EQ(result.status().message().rfind(std::string("mesh importer: cannot start '") + path + "'", 0), 0u)
        << result.status().message();
  }
}

TEST_F(SandboxedImportTest, LargeBinaryStlDoesNotDeadlock) {
  const std::string bytes = GridStl(1000, 500);  // a million triangles, 50 MB
  ASSERT_GT(bytes.size(), 50'000'000u);
  auto local = ImportMesh(bytes, MeshFileFormat::kAuto, 1.0);
  auto isolated = ImportMeshIsolated(bytes, MeshFileFormat::kAuto, 1.0, Sandbox());
  ASSERT_TRUE(local.ok()) << local.status().ToString();
  ASSERT_TRUE(isolated.ok()) << isolated.status().ToString();
  EXPECT_EQ(isolated->triangles.size(), 1'000'000u);
  ExpectSameMesh(*local, *isolated);
}

TEST_F(SandboxedImportTest, MemoryLimitIsResourceExhausted) {
  ImportSandbox sandbox = Sandbox();
  sandbox.memory_limit_bytes = 64 << 20;
  auto result = ImportMeshIsolated(GridStl(300, 300), MeshFileFormat::kStl, 1.0, sandbox);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), StatusCode::kResourceExhausted) << result.status().ToString();
  EXPECT_NE(result.status().message().find("64 MiB"), std::string::npos) << result.status().message();
}

TEST_F(SandboxedImportTest, ChildThatEchoesWhileReadingDoesNotDeadlock) {
  std::string input(50 << 20, '\0');
  for (size_t i = 0; i < input.size(); ++i) input[i] = static_cast<char>(i * 7919 >> 3);
  auto run = RunChild({"/bin/cat"}, input, 60s, input.size());
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  EXPECT_FALSE(run->timed_out);
  EXPECT_FALSE(run->output_too_large);
  EXPECT_TRUE(WIFEXITED(run->wait_status) && WEXITSTATUS(run->wait_status) == 0);
  EXPECT_TRUE(run->output == input);

  auto capped = RunChild({"/bin/cat"}, input, 60s, 1 << 20);
  ASSERT_TRUE(capped.ok()) << capped.status().ToString();
  EXPECT_TRUE(capped->output_too_large);
}

TEST_F(SandboxedImportTest, ConcurrentImportsKeepTheirPipesApart) {
  // A pipe end inherited by a sibling child would keep stdin open and make imports time out.
  std::vector<std::thread> threads;
  std::atomic<int> good = 0;
  for (int t = 0; t < 6; ++t) {
    threads.emplace_back([&good] {
      for (int i = 0; i < 8; ++i) {
        auto mesh = ImportMeshIsolated(kSandboxTrianglePly, MeshFileFormat::kPly, 1.0, Sandbox(20s));
        if (mesh.ok() && mesh->triangles.size() == 1) ++good;
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(good.load(), 48);
}

}  // namespace
}  // namespace vscan::geometry
