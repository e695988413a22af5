// RunChild's child: dies with the thread that started it, starts with default signal handling
// and an empty mask, inherits no descriptor but its stdin, stdout and stderr, and holds the data
// limit it was given.

#include "geometry/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

namespace vscan::geometry {
namespace {

using namespace std::chrono_literals;

// Alive and not a zombie waiting for its new parent to reap it.
bool Running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const size_t end_of_name = line.rfind(')');
  return end_of_name != std::string::npos && end_of_name + 2 < line.size() && line[end_of_name + 2] != 'Z';
}

TEST(ChildProcessTest, ChildDiesWithItsParent) {
  char pattern[] = "/tmp/vscan-child-test-XXXXXX";
  ASSERT_NE(mkdtemp(pattern), nullptr);
  const std::filesystem::path dir = pattern;
  const std::string pid_file = (dir / "pid").string();
  const pid_t parent = fork();
  ASSERT_GE(parent, 0);
  if (parent == 0) {
    // The grandchild records its pid, then outlives any test unless it dies with its parent.
    const std::string script = "echo $$ > " + pid_file + ".tmp && mv " + pid_file + ".tmp " + pid_file +
                               " && exec sleep 60";
    auto run = RunChild({"/bin/sh", "-c", script}, "", 120s, 1024);
    _exit(run.ok() ? 0 : 1);
  }
  pid_t child = 0;
  for (auto deadline = std::chrono::steady_clock::now() + 20s; child == 0;) {
    std::ifstream in(pid_file);
    if (!(in >> child)) child = 0;
    if (child == 0 && std::chrono::steady_clock::now() > deadline) break;
    if (child == 0) std::this_thread::sleep_for(10ms);
  }
  kill(parent, SIGKILL);
  waitpid(parent, nullptr, 0);
  ASSERT_GT(child, 0) << "the grandchild never wrote its pid";

  bool gone = false;
  for (auto deadline = std::chrono::steady_clock::now() + 5s; !gone && std::chrono::steady_clock::now() < deadline;) {
    gone = !Running(child);
    if (!gone) std::this_thread::sleep_for(10ms);
  }
  if (!gone) kill(child, SIGKILL);
  EXPECT_TRUE(gone) << "the child outlived its parent";
  std::filesystem::remove_all(dir);
}

TEST(ChildProcessTest, ChildGetsDefaultSignalHandlingAndAnEmptyMask) {
  struct sigaction ignore {}, previous_action {};
  ignore.sa_handler = SIG_IGN;
  ASSERT_EQ(sigaction(SIGTERM, &ignore, &previous_action), 0);
  sigset_t usr1, previous_mask;
  sigemptyset(&usr1);
  sigaddset(&usr1, SIGUSR1);
  ASSERT_EQ(pthread_sigmask(SIG_BLOCK, &usr1, &previous_mask), 0);
  // A shell cannot undo a signal ignored when it started; blocked, SIGUSR1 would wait forever.
  auto term = RunChild({"/bin/sh", "-c", "kill -TERM $$; echo survived"}, "", 60s, 1024);
  auto usr = RunChild({"/bin/sh", "-c", "kill -USR1 $$; echo survived"}, "", 60s, 1024);
  sigaction(SIGTERM, &previous_action, nullptr);
  pthread_sigmask(SIG_SETMASK, &previous_mask, nullptr);
  ASSERT_TRUE(term.ok()) << term.status().ToString();
  ASSERT_TRUE(usr.ok()) << usr.status().ToString();
  EXPECT_TRUE(WIFSIGNALED(term->wait_status) && WTERMSIG(term->wait_status) == SIGTERM) << term->output;
  EXPECT_TRUE(WIFSIGNALED(usr->wait_status) && WTERMSIG(usr->wait_status) == SIGUSR1) << usr->output;
}

TEST(ChildProcessTest, ChildInheritsNoOtherDescriptor) {
  const int opened = open("/dev/null", O_RDONLY);
  const int inheritable = fcntl(opened, F_DUPFD, 50);  // F_DUPFD: without close-on-exec
  close(opened);
  ASSERT_GE(inheritable, 50);
  const std::string path = "/proc/$$/fd/" + std::to_string(inheritable);
  auto run = RunChild({"/bin/sh", "-c", "test -e " + path + " && echo leaked || echo clean"}, "", 60s, 1024);
  close(inheritable);
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  EXPECT_EQ(run->output, "clean\n");
  auto stdio = RunChild({"/bin/sh", "-c", "test -e /proc/$$/fd/2 && cat"}, "in", 60s, 1024);
  ASSERT_TRUE(stdio.ok()) << stdio.status().ToString();
  EXPECT_EQ(stdio->output, "in");
}

TEST(ChildProcessTest, AMemoryBoundIsTheChildsDataLimit) {
  const std::string script = "grep 'Max data size' /proc/$$/limits | tr -s ' '";
  auto bounded = RunChild({"/bin/sh", "-c", script}, "", 60s, 1024, nullptr, uint64_t{64} << 20);
  ASSERT_TRUE(bounded.ok()) << bounded.status().ToString();
  EXPECT_EQ(bounded->output, "Max data size 67108864 67108864 bytes \n");
  auto unbounded = RunChild({"/bin/sh", "-c", script}, "", 60s, 1024);
  ASSERT_TRUE(unbounded.ok()) << unbounded.status().ToString();
  EXPECT_EQ(unbounded->output.find("67108864"), std::string::npos) << unbounded->output;
}

TEST(ChildProcessTest, ProgramThatCannotStartIsUnavailable) {
  auto run = RunChild({"/nonexistent/program"}, "", 60s, 1024);
  ASSERT_FALSE(run.ok());
  EXPECT_EQ(run.status().code(), StatusCode::kUnavailable);
  EXPECT_NE(run.status().message().find("cannot start '/nonexistent/program': No such file or directory"),
            std::string::npos)
      << run.status().message();
}

}  // namespace
}  // namespace vscan::geometry
