#pragma once
// A dataset directory measured as a job writes it: the whole tree at the start and the end of a
// run, and between scenes only the scene directories that appeared, so that a scene costs a listing
// of train_pbr and a walk of its own files, however many scenes came before.

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>

#include "vscan/common/status.h"

namespace vscan::service {

class DatasetSpaceMeter {
 public:
  explicit DatasetSpaceMeter(std::filesystem::path root);
  // Every regular file under the root.
  StatusOr<uint64_t> MeasureAll();
  // The last measure plus the finished scene directories that appeared since.
  StatusOr<uint64_t> MeasureNewScenes();

 private:
  const std::filesystem::path root_;
  std::set<std::string> scenes_;  // finished scene directories counted
  uint64_t bytes_ = 0;
};

}  // namespace vscan::service
