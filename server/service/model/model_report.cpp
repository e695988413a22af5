#include "service/model/model_report.h"

#include <algorithm>

namespace vscan::service {
namespace {

template <typename Get>
ErrorSummary Summarise(const std::vector<ScanAlignmentRecord>& scans, bool aligned_only, Get get) {
  ErrorSummary s;
  for (const ScanAlignmentRecord& scan : scans) {
    if (!scan.has_error || (aligned_only && !scan.aligned)) continue;
    const double x = get(scan);
    s.mean += x;
    s.max = std::max(s.max, x);
    ++s.count;
  }
  if (s.count) s.mean /= static_cast<double>(s.count);
  return s;
}

}  // namespace

ErrorSummary SummariseFinalRotation(const std::vector<ScanAlignmentRecord>& scans) {
  return Summarise(scans, true, [](const ScanAlignmentRecord& s) { return s.rotation_error_deg; });
}

ErrorSummary SummariseFinalTranslation(const std::vector<ScanAlignmentRecord>& scans) {
  return Summarise(scans, true, [](const ScanAlignmentRecord& s) { return s.translation_error_m; });
}

ErrorSummary SummariseInitialRotation(const std::vector<ScanAlignmentRecord>& scans) {
  return Summarise(scans, false, [](const ScanAlignmentRecord& s) { return s.initial_rotation_error_deg; });
}

ErrorSummary SummariseInitialTranslation(const std::vector<ScanAlignmentRecord>& scans) {
  return Summarise(scans, false, [](const ScanAlignmentRecord& s) { return s.initial_translation_error_m; });
}

}  // namespace vscan::service
