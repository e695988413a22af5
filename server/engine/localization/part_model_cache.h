#pragma once
// Part models kept between searches: building one (sampling, the pair table) costs a good share of
// a search, and a cell localizes the same parts scan after scan.

#include <cstddef>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "localization/part_model.h"
#include "vscan/common/status.h"

namespace vscan::localization {

class PartModelCache {
 public:
  // At most `capacity` models and about max_bytes of them (the newest is kept whatever its size).
  explicit PartModelCache(size_t capacity = 8, size_t max_bytes = size_t{512} << 20)
      : capacity_(capacity), max_bytes_(max_bytes) {}

  // The model kept under key, or the one build makes (kept when it succeeds; the least recently
  // used ones leave while more than capacity, or more than max_bytes, are kept). Two callers
  // missing at once may both build.
  StatusOr<std::shared_ptr<const PartModel>> Get(const std::string& key,
                                                 const std::function<StatusOr<PartModel>()>& build);

  size_t size() const;
  size_t bytes() const;

 private:
  size_t capacity_, max_bytes_;
  mutable std::mutex mutex_;
  std::list<std::pair<std::string, std::shared_ptr<const PartModel>>> kept_;  // most recent first
};

// The cache key of a mesh (by the caller's name for it) at a scale under the settings a model is
// built with.
std::string PartModelKey(const std::string& mesh_name, double scale, const PartModelSettings& settings);

}  // namespace vscan::localization
