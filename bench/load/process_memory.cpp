#include "process_memory.h"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace vscan::cli {
namespace {

constexpr const char* kListenState = "0A";

// "Name:   1234 kB" -> 1234.
std::optional<uint64_t> KibField(const std::string& line, const std::string& name) {
  if (!line.starts_with(name)) return std::nullopt;
  std::istringstream fields(line.substr(name.size()));
  uint64_t value = 0;
  if (!(fields >> value)) return std::nullopt;
  return value;
}

// Inodes of listening sockets on port in one /proc/net/tcp-style table.
void ListeningInodes(const char* table, uint16_t port, std::set<std::string>* inodes) {
  std::ifstream in(table);
  std::string line;
  std::getline(in, line);  // column titles
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
    if (!(fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode)) {
      continue;
    }
    const size_t colon = local.rfind(':');
    if (state != kListenState || colon == std::string::npos) continue;
    unsigned local_port = 0;
    const char* begin = local.data() + colon + 1;
    const char* end = local.data() + local.size();
    if (std::from_chars(begin, end, local_port, 16).ec == std::errc() && local_port == port) inodes->insert(inode);
  }
}

}  // namespace

std::optional<ProcessMemory> ReadProcessMemory(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  if (!in) return std::nullopt;
  ProcessMemory memory;
  bool rss = false;
  bool peak = false;
  for (std::string line; std::getline(in, line);) {
    if (const auto v = KibField(line, "VmRSS:")) memory.rss_kib = *v, rss = true;
    if (const auto v = KibField(line, "VmHWM:")) memory.peak_rss_kib = *v, peak = true;
  }
  if (!rss || !peak) return std::nullopt;
  return memory;
}

std::optional<pid_t> FindListeningProcess(uint16_t port) {
  std::set<std::string> inodes;
  ListeningInodes("/proc/net/tcp", port, &inodes);
  ListeningInodes("/proc/net/tcp6", port, &inodes);
  inodes.erase("0");
  if (inodes.empty()) return std::nullopt;
  namespace fs = std::filesystem;
  // Processes end and close files while we look: every step takes an error code and moves on.
  std::error_code ec;
  for (fs::directory_iterator proc("/proc", ec), done; !ec && proc != done; proc.increment(ec)) {
    const std::string name = proc->path().filename().string();
    pid_t pid = 0;
    const auto parsed = std::from_chars(name.data(), name.data() + name.size(), pid);
    if (parsed.ec != std::errc() || parsed.ptr != name.data() + name.size()) continue;
    std::error_code fd_ec;
    for (fs::directory_iterator fd(proc->path() / "fd", fd_ec), fd_done; !fd_ec && fd != fd_done;
         fd.increment(fd_ec)) {
      std::error_code link_ec;
      const std::string target = fs::read_symlink(fd->path(), link_ec).string();
      if (link_ec || !target.starts_with("socket:[")) continue;
      if (inodes.contains(target.substr(8, target.size() - 9))) return pid;
    }
  }
  return std::nullopt;
}

}  // namespace vscan::cli
