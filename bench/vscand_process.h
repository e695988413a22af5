#pragma once
// A vscand in a process of its own, on a free loopback port with a fresh data directory that is
// removed when it stops.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "child_process.h"

namespace vscan::bench {

class VscandProcess {
 public:
  // Starts vscand_path with extra_flags and waits until it listens; throws if it does not.
  VscandProcess(const std::string& vscand_path, const std::vector<std::string>& extra_flags);
  ~VscandProcess();

  // "127.0.0.1:PORT"
  const std::string& address() const { return address_; }

 private:
  std::filesystem::path dir_;
  std::unique_ptr<ChildProcess> process_;
  std::string address_;
};

}  // namespace vscan::bench
