// The data directory lock: one holder at a time, named in the refusal, released when its
// process dies however it dies, and never inherited by a program the holder runs.

#include "guards/data_dir_lock.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

extern char** environ;

namespace vscan::guards {
namespace {

class DataDirLockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/vscan-lock-test-XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_;
};

void ExpectRefused(const StatusOr<DataDirLock>& lock, pid_t holder, const std::filesystem::path& dir) {
  ASSERT_FALSE(lock.ok());
  EXPECT_EQ(lock.status().code(), StatusCode::kFailedPrecondition) << lock.status().ToString();
  EXPECT_NE(lock.status().message().find("'" + dir.string() + "' is in use by another vscand (pid " +
                                         std::to_string(holder) + ")"),
            std::string::npos)
      << lock.status().message();
}

TEST_F(DataDirLockTest, OneHolderAtATimeAndTheFileNamesIt) {
  std::optional<DataDirLock> first;
  {
    auto lock = DataDirLock::Acquire(dir_);
    ASSERT_TRUE(lock.ok()) << lock.status().ToString();
    first.emplace(std::move(lock).value());
  }
  std::ifstream pid_file(dir_ / "vscand.lock");
  pid_t written = 0;
  pid_file >> written;
  EXPECT_EQ(written, getpid());

  ExpectRefused(DataDirLock::Acquire(dir_), getpid(), dir_);
  first.reset();
  EXPECT_TRUE(DataDirLock::Acquire(dir_).ok());
}

TEST_F(DataDirLockTest, ReleasedWhenTheHolderIsKilled) {
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t holder = fork();
  ASSERT_GE(holder, 0);
  if (holder == 0) {
    auto lock = DataDirLock::Acquire(dir_);
    const char byte = lock.ok() ? 1 : 0;
    if (write(ready[1], &byte, 1) != 1) _exit(1);
    for (;;) pause();
  }
  close(ready[1]);
  char byte = 0;
  ASSERT_EQ(read(ready[0], &byte, 1), 1);
  close(ready[0]);
  ASSERT_EQ(byte, 1) << "the child could not take the lock";

  ExpectRefused(DataDirLock::Acquire(dir_), holder, dir_);
  kill(holder, SIGKILL);
  ASSERT_EQ(waitpid(holder, nullptr, 0), holder);
  auto after = DataDirLock::Acquire(dir_);
  EXPECT_TRUE(after.ok()) << after.status().ToString();
}

TEST_F(DataDirLockTest, NotInheritedByProgramsTheHolderRuns) {
  pid_t sleeper = -1;
  {
    auto lock = DataDirLock::Acquire(dir_);
    ASSERT_TRUE(lock.ok()) << lock.status().ToString();
    char sleep_path[] = "/bin/sleep";
    char seconds[] = "30";
    char* argv[] = {sleep_path, seconds, nullptr};
    ASSERT_EQ(posix_spawn(&sleeper, sleep_path, nullptr, nullptr, argv, environ), 0);
  }
  auto again = DataDirLock::Acquire(dir_);
  EXPECT_TRUE(again.ok()) << again.status().ToString();
  kill(sleeper, SIGKILL);
  waitpid(sleeper, nullptr, 0);
}

TEST_F(DataDirLockTest, MissingDirectoryIsUnavailable) {
  auto lock = DataDirLock::Acquire(dir_ / "missing");
  ASSERT_FALSE(lock.ok());
  EXPECT_EQ(lock.status().code(), StatusCode::kUnavailable);
  EXPECT_NE(lock.status().message().find("--data-dir: cannot open"), std::string::npos) << lock.status().message();
}

}  // namespace
}  // namespace vscan::guards
