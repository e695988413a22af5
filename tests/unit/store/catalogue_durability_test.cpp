// A child process writes and acknowledges each write over a pipe, then dies by SIGKILL mid-stream;
// everything it acknowledged must be in the database afterwards.

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "store/catalogue.h"
#include "vscan_test/temp_dir.h"

namespace vscan::store {
namespace {

constexpr int kAcksBeforeKill = 20;

void WriteLine(int fd, const std::string& line) {
  std::string data = line + "\n";
  const char* p = data.data();
  size_t left = data.size();
  while (left > 0) {
    ssize_t n = ::write(fd, p, left);
    if (n <= 0) ::_exit(5);
    p += n;
    left -= static_cast<size_t>(n);
  }
}

[[noreturn]] void RunChild(const std::filesystem::path& db_path, int ack_fd) {
  auto opened = Catalogue::Open(db_path);
  if (!opened.ok()) ::_exit(2);
  Catalogue& catalogue = **opened;
  MeshRecord mesh_in;
  mesh_in.name = "cube";
  mesh_in.sha256 = std::string(64, 'c');
  auto mesh = catalogue.InsertMesh(mesh_in);
  auto scene = mesh.ok() ? catalogue.CreateScene("durable") : StatusOr<SceneRecord>(mesh.status());
  if (!scene.ok()) ::_exit(3);
  WriteLine(ack_fd, scene->scene_id + " " + mesh->mesh_id);
  for (;;) {
    ObjectRecord object;
    object.scene_id = scene->scene_id;
    object.mesh_id = mesh->mesh_id;
    auto added = catalogue.AddObject(object);
    if (!added.ok()) ::_exit(4);
    WriteLine(ack_fd, std::to_string(added->second));
  }
}

// Reads one '\n'-terminated line, waiting at most 30 s; empty on EOF or timeout.
std::string ReadLine(int fd, std::string& buffer) {
  for (;;) {
    if (size_t eol = buffer.find('\n'); eol != std::string::npos) {
      std::string line = buffer.substr(0, eol);
      buffer.erase(0, eol + 1);
      return line;
    }
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 30'000) <= 0) return {};
    char chunk[256];
    ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n <= 0) return {};
    buffer.append(chunk, static_cast<size_t>(n));
  }
}

TEST(CatalogueDurabilityTest, AcknowledgedWritesSurviveSigkill) {
  test::TempDir dir;
  ASSERT_FALSE(dir.path().empty());
  const auto db_path = dir.path() / "catalogue.db";
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);

  pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(fds[0]);
    RunChild(db_path, fds[1]);
  }
  ::close(fds[1]);

  std::string buffer;
  std::istringstream header(ReadLine(fds[0], buffer));
  std::string scene_id, mesh_id;
  header >> scene_id >> mesh_id;
  uint64_t last_acked_revision = 0;
  for (int i = 0; i < kAcksBeforeKill && !scene_id.empty(); ++i) {
    std::string line = ReadLine(fds[0], buffer);
    if (line.empty()) break;
    last_acked_revision = std::stoull(line);
  }
  ::kill(child, SIGKILL);
  int wait_status = 0;
  ASSERT_EQ(::waitpid(child, &wait_status, 0), child);
  ::close(fds[0]);
  ASSERT_TRUE(WIFSIGNALED(wait_status) && WTERMSIG(wait_status) == SIGKILL)
      << "child ended early with status " << wait_status;
  ASSERT_FALSE(scene_id.empty());
  ASSERT_EQ(last_acked_revision, static_cast<uint64_t>(1 + kAcksBeforeKill));

  auto opened = Catalogue::Open(db_path);
  ASSERT_TRUE(opened.ok()) << opened.status().ToString();
  auto scene = (*opened)->GetScene(scene_id);
  ASSERT_TRUE(scene.ok()) << scene.status().ToString();
  EXPECT_EQ(scene->name, "durable");
  EXPECT_GE(scene->revision, last_acked_revision);
  EXPECT_GE(scene->objects.size(), static_cast<size_t>(kAcksBeforeKill));
  EXPECT_EQ(scene->objects.size() + 1, scene->revision);  // the last add was whole or absent
  EXPECT_TRUE((*opened)->GetMesh(mesh_id).ok());
}

// Ids come from a per-thread generator; a forked child must not repeat its parent's sequence.
TEST(CatalogueDurabilityTest, ForkedProcessesDrawDifferentIds) {
  test::TempDir dir;
  ASSERT_FALSE(dir.path().empty());
  auto opened = Catalogue::Open(dir.path() / "catalogue.db");
  ASSERT_TRUE(opened.ok()) << opened.status().ToString();
  ASSERT_TRUE((*opened)->CreateScene("before fork").ok());  // seeds this thread's generator
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);

  pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(fds[0]);
    // A connection must not cross a fork: the child opens its own.
    auto own = Catalogue::Open(dir.path() / "catalogue.db");
    auto scene = own.ok() ? (*own)->CreateScene("child") : StatusOr<SceneRecord>(own.status());
    if (!scene.ok()) ::_exit(2);
    WriteLine(fds[1], scene->scene_id);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string buffer;
  std::string child_id = ReadLine(fds[0], buffer);
  ::close(fds[0]);
  int wait_status = 0;
  ASSERT_EQ(::waitpid(child, &wait_status, 0), child);
  ASSERT_FALSE(child_id.empty());

  auto parent_scene = (*opened)->CreateScene("parent");
  ASSERT_TRUE(parent_scene.ok());
  EXPECT_NE(parent_scene->scene_id, child_id);
}

}  // namespace
}  // namespace vscan::store
