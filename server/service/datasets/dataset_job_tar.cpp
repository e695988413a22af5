#include "service/datasets/dataset_job_tar.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace vscan::service {
namespace {

constexpr size_t kBlock = 512;

void Octal(char* field, size_t width, uint64_t value) {
  std::snprintf(field, width, "%0*llo", static_cast<int>(width - 1), static_cast<unsigned long long>(value));
}

std::string Header(const std::string& name, uint64_t size) {
  std::string header(kBlock, '\0');
  char* h = header.data();
  std::memcpy(h, name.data(), name.size());
  Octal(h + 100, 8, 0644);
  Octal(h + 108, 8, 0);
  Octal(h + 116, 8, 0);
  Octal(h + 124, 12, size);
  Octal(h + 136, 12, 0);
  h[156] = '0';
  std::memcpy(h + 257, "ustar", 6);
  std::memcpy(h + 263, "00", 2);
  std::memset(h + 148, ' ', 8);
  unsigned sum = 0;
  for (const char c : header) sum += static_cast<unsigned char>(c);
  std::snprintf(h + 148, 8, "%06o", sum);
  return header;
}

}  // namespace

StatusOr<std::string> TarDirectory(const std::filesystem::path& root, uint64_t max_bytes,
                                   const std::atomic<bool>* cancel) {
  std::vector<std::string> paths;
  uint64_t total = 0;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(root, ec); !ec && it != end(it); it.increment(ec)) {
    if (!it->is_regular_file()) continue;
    paths.push_back(std::filesystem::relative(it->path(), root).generic_string());
    total += it->file_size();
  }
  if (ec) return Internal("cannot list " + root.string() + ": " + ec.message());
  if (total > max_bytes) {
    return FailedPrecondition("the dataset holds " + std::to_string(total) + " bytes, more than the " +
                              std::to_string(max_bytes) + " one artifact may hold");
  }
  std::sort(paths.begin(), paths.end());
  std::string tar;
  tar.reserve(total + paths.size() * 2 * kBlock + 2 * kBlock);
  for (const std::string& path : paths) {
    if (cancel != nullptr && cancel->load()) return Cancelled("dataset.tar: stopped");
    if (path.size() >= 100) return FailedPrecondition("'" + path + "' is too long a name for a tar header");
    std::ifstream in(root / path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (!in) return Internal("cannot read " + (root / path).string());
    const std::string data = bytes.str();
    tar += Header(path, data.size());
    tar += data;
    tar.append((kBlock - data.size() % kBlock) % kBlock, '\0');
  }
  tar.append(2 * kBlock, '\0');
  return tar;
}

}  // namespace vscan::service
