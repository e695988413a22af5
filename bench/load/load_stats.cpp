#include "load_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vscan::cli {

const char* LoadKindName(LoadKind kind) {
  switch (kind) {
    case LoadKind::kScan:
      return "scan";
    case LoadKind::kIk:
      return "ik";
    case LoadKind::kCatalogue:
      return "catalogue";
  }
  return "?";
}

LatencySummary Summarize(std::vector<double> samples_ms) {
  LatencySummary summary;
  summary.count = samples_ms.size();
  if (samples_ms.empty()) return summary;
  std::sort(samples_ms.begin(), samples_ms.end());
  const auto rank = [&](double p) {
    const auto index = static_cast<size_t>(std::ceil(p * static_cast<double>(samples_ms.size())));
    return samples_ms[std::clamp<size_t>(index, 1, samples_ms.size()) - 1];
  };
  summary.p50_ms = rank(0.50);
  summary.p99_ms = rank(0.99);
  summary.max_ms = samples_ms.back();
  summary.mean_ms = std::accumulate(samples_ms.begin(), samples_ms.end(), 0.0) / static_cast<double>(summary.count);
  return summary;
}

void LoadTally::Merge(const LoadTally& other) {
  for (size_t k = 0; k < kLoadKinds; ++k) {
    ok_ms[k].insert(ok_ms[k].end(), other.ok_ms[k].begin(), other.ok_ms[k].end());
    for (const auto& [code, n] : other.errors[k]) errors[k][code] += n;
  }
  scan_points += other.scan_points;
}

uint64_t LoadTally::Failed(LoadKind kind) const {
  uint64_t n = 0;
  for (const auto& [code, count] : errors[static_cast<size_t>(kind)]) n += count;
  return n;
}

}  // namespace vscan::cli
