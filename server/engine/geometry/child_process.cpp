#include "geometry/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <system_error>
#include <thread>

extern char** environ;

namespace vscan::geometry {
namespace {

using Clock = std::chrono::steady_clock;

constexpr size_t kReadChunk = size_t{1} << 16;
constexpr size_t kWriteChunk = size_t{1} << 20;
constexpr std::chrono::milliseconds kMaxReapPause{20};

std::string ErrorText(int error) { return std::generic_category().message(error); }

class Fd {
 public:
  Fd() = default;
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { Reset(); }

  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  void Reset(int fd = -1) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }

 private:
  int fd_ = -1;
};

struct Pipe {
  Fd read;
  Fd write;
};

// Both ends are close-on-exec so that a child started by another thread meanwhile cannot
// inherit them (it would hold our child's stdin open), and above the standard descriptors so
// that the child's dup2 onto 0 and 1 cannot overwrite one another.
Status OpenPipe(Pipe& pipe) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return Unavailable("cannot create a pipe: " + ErrorText(errno));
  pipe.read.Reset(fds[0]);
  pipe.write.Reset(fds[1]);
  for (Fd* end : {&pipe.read, &pipe.write}) {
    if (end->get() > STDERR_FILENO) continue;
    int moved = ::fcntl(end->get(), F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
    if (moved < 0) return Unavailable("cannot move a pipe descriptor: " + ErrorText(errno));
    end->Reset(moved);
  }
  return Status::Ok();
}

Status SetNonBlocking(const Fd& fd) {
  int flags = ::fcntl(fd.get(), F_GETFL);
  if (flags < 0 || ::fcntl(fd.get(), F_SETFL, flags | O_NONBLOCK) < 0) {
    return Unavailable("cannot make a pipe non-blocking: " + ErrorText(errno));
  }
  return Status::Ok();
}

// Writing to a child that has exited raises SIGPIPE in the writing thread; while blocked, the
// write fails with EPIPE instead, and a SIGPIPE left pending by it is consumed on the way out.
class SigpipeBlocked {
 public:
  SigpipeBlocked() {
    sigemptyset(&sigpipe_);
    sigaddset(&sigpipe_, SIGPIPE);
    was_pending_ = IsPending();
    pthread_sigmask(SIG_BLOCK, &sigpipe_, &previous_);
  }
  SigpipeBlocked(const SigpipeBlocked&) = delete;
  SigpipeBlocked& operator=(const SigpipeBlocked&) = delete;
  ~SigpipeBlocked() {
    if (!was_pending_ && IsPending()) {
      const timespec no_wait{};
      sigtimedwait(&sigpipe_, nullptr, &no_wait);
    }
    pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
  }

 private:
  static bool IsPending() {
    sigset_t pending;
    sigemptyset(&pending);
    sigpending(&pending);
    return sigismember(&pending, SIGPIPE) == 1;
  }

  sigset_t sigpipe_;
  sigset_t previous_;
  bool was_pending_ = false;
};

// Closes [first, last]; async-signal-safe. The loop, up to max_fd, is for kernels before 5.9.
void CloseDescriptors(unsigned first, unsigned last, int max_fd) {
  if (first > last || ::close_range(first, last, 0) == 0) return;
  for (unsigned fd = first; fd <= last && fd < static_cast<unsigned>(max_fd); ++fd) ::close(static_cast<int>(fd));
}

// Tells the parent why the child could not exec, and ends it.
[[noreturn]] void ExecFailed(int error_fd, int error) {
  [[maybe_unused]] ssize_t n = ::write(error_fd, &error, sizeof(error));
  ::_exit(127);
}

// Runs in the forked child, so only async-signal-safe calls: the parent has other threads, whose
// locks may be held forever here. Reports why it could not exec through error_fd.
[[noreturn]] void ExecChild(char* const* args, int stdin_fd, int stdout_fd, int error_fd, pid_t parent,
                            int max_fd, uint64_t max_memory_bytes) {
  // Dies with the thread that started it (RunChild waits for it there), so that a killed server
  // leaves no helper behind; a parent that died before the prctl is caught by getppid.
  if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) ExecFailed(error_fd, errno);
  if (::getppid() != parent) ::_exit(127);
  // RLIMIT_DATA counts the heap and every private writable mapping: the child's allocations fail
  // past it, rather than the machine running out.
  if (max_memory_bytes > 0) {
    const rlimit limit{max_memory_bytes, max_memory_bytes};
    if (::setrlimit(RLIMIT_DATA, &limit) != 0) ExecFailed(error_fd, errno);
  }
  // Default handlers and an empty mask: the server blocks its stop signals and may ignore
  // SIGPIPE, and both would otherwise carry over through exec.
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  for (int sig = 1; sig < NSIG; ++sig) ::sigaction(sig, &default_action, nullptr);
  if (::dup2(stdin_fd, STDIN_FILENO) < 0 || ::dup2(stdout_fd, STDOUT_FILENO) < 0) ExecFailed(error_fd, errno);
  const int null_fd = ::open("/dev/null", O_WRONLY);
  if (null_fd < 0 || ::dup2(null_fd, STDERR_FILENO) < 0) ExecFailed(error_fd, errno);
  // Nothing else is inherited; error_fd is close-on-exec and closes itself.
  CloseDescriptors(STDERR_FILENO + 1, error_fd - 1, max_fd);
  CloseDescriptors(error_fd + 1, ~0u, max_fd);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  ::execve(args[0], args, environ);
  ExecFailed(error_fd, errno);
}

// fork and exec rather than posix_spawn, which cannot tie the child's life to ours.
StatusOr<pid_t> Spawn(const std::vector<std::string>& argv, int stdin_fd, int stdout_fd, uint64_t max_memory_bytes) {
  const std::string& path = argv.front();
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  Pipe exec_error;
  RETURN_IF_ERROR(OpenPipe(exec_error));
  const pid_t parent = ::getpid();
  const int max_fd = static_cast<int>(std::clamp<long>(::sysconf(_SC_OPEN_MAX), 1024, INT_MAX));
  // Blocked across the fork so that none of the server's handlers can run in the child.
  sigset_t all, previous;
  sigfillset(&all);
  pthread_sigmask(SIG_SETMASK, &all, &previous);
  const pid_t pid = ::fork();
  if (pid == 0) ExecChild(args.data(), stdin_fd, stdout_fd, exec_error.write.get(), parent, max_fd, max_memory_bytes);
  const int fork_error = errno;
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  if (pid < 0) return Unavailable("cannot start '" + path + "': " + ErrorText(fork_error));

  // The pipe closes at the child's exec, or carries the errno of what failed before it.
  exec_error.write.Reset();
  int child_error = 0;
  ssize_t n;
  do {
    n = ::read(exec_error.read.get(), &child_error, sizeof(child_error));
  } while (n < 0 && errno == EINTR);
  if (n != sizeof(child_error)) return pid;
  while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
  }
  return Unavailable("cannot start '" + path + "': " + ErrorText(child_error));
}

int PollTimeoutMs(Clock::duration remaining) {
  auto ms = std::chrono::ceil<std::chrono::milliseconds>(remaining).count();
  return static_cast<int>(std::clamp<decltype(ms)>(ms, 0, INT_MAX));
}

// Feeds the input and drains the output together: a child that writes before it has read all
// of its input would otherwise fill one pipe while we wait on the other. Stops at the child's
// end of output, at the deadline or past max_output.
Status Exchange(Fd& to_child, Fd& from_child, std::string_view input, Clock::time_point deadline,
                size_t max_output, const std::atomic<bool>* cancel, ChildOutcome& outcome) {
  size_t written = 0;
  if (input.empty()) to_child.Reset();
  while (from_child.valid()) {
    const auto now = Clock::now();
    if (now >= deadline) {
      outcome.timed_out = true;
      return Status::Ok();
    }
    if (cancel != nullptr && cancel->load()) {
      outcome.cancelled = true;
      return Status::Ok();
    }
    // A child that computes long before it writes is watched in short waits, for the cancel flag.
    auto wait = deadline - now;
    if (cancel != nullptr) wait = std::min<Clock::duration>(wait, kCancelPollInterval);
    pollfd fds[2] = {{from_child.get(), POLLIN, 0}, {to_child.get(), POLLOUT, 0}};
    const nfds_t count = to_child.valid() ? 2 : 1;
    if (::poll(fds, count, PollTimeoutMs(wait)) < 0) {
      if (errno == EINTR) continue;
      return Internal("poll on the child's pipes failed: " + ErrorText(errno));
    }
    if (count == 2 && fds[1].revents != 0) {
      ssize_t n = ::write(to_child.get(), input.data() + written, std::min(input.size() - written, kWriteChunk));
      if (n > 0) {
        written += static_cast<size_t>(n);
        if (written == input.size()) to_child.Reset();
      } else if (n < 0 && errno != EAGAIN && errno != EINTR) {
        to_child.Reset();  // the child stopped reading; how it ended tells the rest
      }
    }
    if (fds[0].revents != 0) {
      const size_t before = outcome.output.size();
      outcome.output.resize(before + kReadChunk);
      ssize_t n = ::read(from_child.get(), outcome.output.data() + before, kReadChunk);
      outcome.output.resize(before + static_cast<size_t>(std::max<ssize_t>(n, 0)));
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        from_child.Reset();
      } else if (outcome.output.size() > max_output) {
        outcome.output_too_large = true;
        return Status::Ok();
      }
    }
  }
  return Status::Ok();
}

// Waits for the child, killing it if it outlives the deadline; returns its wait status.
int Reap(pid_t pid, Clock::time_point deadline, bool& timed_out) {
  std::chrono::milliseconds pause{1};
  for (;;) {
    int status = 0;
    pid_t reaped = ::waitpid(pid, &status, timed_out ? 0 : WNOHANG);
    if (reaped == pid) return status;
    if (reaped < 0) {
      if (errno == EINTR) continue;
      return 0;  // ECHILD: SIGCHLD is ignored, so the kernel reaped it; the output has to tell
    }
    if (Clock::now() >= deadline) {
      ::kill(pid, SIGKILL);
      timed_out = true;
      continue;
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, kMaxReapPause);
  }
}

}  // namespace

StatusOr<ChildOutcome> RunChild(const std::vector<std::string>& argv, std::string_view input,
                                std::chrono::milliseconds timeout, size_t max_output,
                                const std::atomic<bool>* cancel, uint64_t max_memory_bytes) {
  if (argv.empty() || argv.front().empty()) return Unavailable("cannot start '': no program given");
  const auto deadline = Clock::now() + timeout;
  Pipe to_child, from_child;
  RETURN_IF_ERROR(OpenPipe(to_child));
  RETURN_IF_ERROR(OpenPipe(from_child));
  RETURN_IF_ERROR(SetNonBlocking(to_child.write));
  RETURN_IF_ERROR(SetNonBlocking(from_child.read));
  SigpipeBlocked sigpipe_blocked;

  ASSIGN_OR_RETURN(pid_t pid, Spawn(argv, to_child.read.get(), from_child.write.get(), max_memory_bytes));
  to_child.read.Reset();
  from_child.write.Reset();

  ChildOutcome outcome;
  Status exchanged = Exchange(to_child.write, from_child.read, input, deadline, max_output, cancel, outcome);
  const bool stop = !exchanged.ok() || outcome.timed_out || outcome.output_too_large || outcome.cancelled;
  if (stop) ::kill(pid, SIGKILL);
  to_child.write.Reset();
  from_child.read.Reset();
  outcome.wait_status = Reap(pid, deadline, outcome.timed_out);
  if (!exchanged.ok()) return exchanged;
  return outcome;
}

}  // namespace vscan::geometry
