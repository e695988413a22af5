#include "service/datasets/dataset_space.h"

#include <system_error>
#include <utility>

#include "service/datasets/format/dataset_layout.h"
#include "store/data_quota.h"

namespace vscan::service {
namespace {

namespace fs = std::filesystem;

bool IsPartial(const std::string& name) {
  const std::string suffix = dataset::kPartialSuffix;
  return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

DatasetSpaceMeter::DatasetSpaceMeter(fs::path root) : root_(std::move(root)) {}

StatusOr<uint64_t> DatasetSpaceMeter::MeasureAll() {
  std::error_code ec;
  const uint64_t bytes = store::RegularFileBytes(root_, ec);
  if (ec) return Unavailable("cannot measure " + root_.string() + ": " + ec.message());
  std::set<std::string> scenes;
  const fs::path scenes_dir = root_ / dataset::kScenesDir;
  if (fs::exists(scenes_dir, ec)) {
    for (auto it = fs::directory_iterator(scenes_dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (!IsPartial(name)) scenes.insert(name);
    }
    if (ec) return Unavailable("cannot list " + scenes_dir.string() + ": " + ec.message());
  }
  scenes_ = std::move(scenes);
  bytes_ = bytes;
  return bytes_;
}

StatusOr<uint64_t> DatasetSpaceMeter::MeasureNewScenes() {
  const fs::path scenes_dir = root_ / dataset::kScenesDir;
  std::error_code ec;
  if (!fs::exists(scenes_dir, ec)) return bytes_;
  uint64_t added = 0;
  std::set<std::string> found;
  for (auto it = fs::directory_iterator(scenes_dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    std::string name = it->path().filename().string();
    if (IsPartial(name) || scenes_.count(name)) continue;
    std::error_code size_ec;
    added += store::RegularFileBytes(it->path(), size_ec);
    if (size_ec) return Unavailable("cannot measure " + it->path().string() + ": " + size_ec.message());
    found.insert(std::move(name));
  }
  if (ec) return Unavailable("cannot list " + scenes_dir.string() + ": " + ec.message());
  scenes_.merge(found);
  bytes_ += added;
  return bytes_;
}

}  // namespace vscan::service
