#include "vscand_process.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <stdexcept>
#include <thread>

namespace vscan::bench {

VscandProcess::VscandProcess(const std::string& vscand_path, const std::vector<std::string>& extra_flags) {
  static std::atomic<int> count{0};
  dir_ = std::filesystem::temp_directory_path() /
         ("vscan-bench-vscand-" + std::to_string(::getpid()) + "-" + std::to_string(count++));
  std::filesystem::create_directories(dir_);
  const std::filesystem::path port_file = dir_ / "port";
  std::vector<std::string> argv = {vscand_path,   "--listen",    "127.0.0.1:0",      "--data-dir",
                                   dir_ / "data", "--port-file", port_file.string(), "--log-level",
                                   "warn"};
  argv.insert(argv.end(), extra_flags.begin(), extra_flags.end());
  process_ = std::make_unique<ChildProcess>(argv, (dir_ / "vscand.log").string());
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < give_up && process_->Running()) {
    int port = 0;
    std::ifstream in(port_file);
    if (in >> port && port > 0) {
      address_ = "127.0.0.1:" + std::to_string(port);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  process_.reset();
  throw std::runtime_error(vscand_path + " did not start listening; see " + (dir_ / "vscand.log").string());
}

VscandProcess::~VscandProcess() {
  process_.reset();
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

}  // namespace vscan::bench
