#pragma once
// Other programs run from a benchmark: spawned with posix_spawn, timed from spawn to reaping.

#include <string>
#include <sys/types.h>
#include <vector>

namespace vscan::bench {

struct ProcessRun {
  int exit_code = -1;  // the signal number + 128 when a signal ended it
  double wall_ms = 0;  // from the spawn to the reaping
  double cpu_ms = 0;   // user + system time of the process
  std::string output;  // what it wrote to stdout
};

// Runs argv[0] (a path) with argv to its end; its stdout goes through a file in scratch_dir
// (so that reading a pipe does not pace the child), stderr stays the benchmark's.
ProcessRun RunProcess(const std::vector<std::string>& argv, const std::string& scratch_dir);

// A long-running child (a server): SIGTERM and reaped when destroyed.
class ChildProcess {
 public:
  // stdout and stderr go to log_path.
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path);
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess();

  // False once it has ended.
  bool Running();

 private:
  pid_t pid_ = -1;
};

}  // namespace vscan::bench
