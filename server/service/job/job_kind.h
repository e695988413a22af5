#pragma once
// The kinds of job vscand runs, by the name the job catalogue stores and Job.kind reports.

#include <string_view>

namespace vscan::service {

enum class JobKind { kCampaign, kModel, kBinFill, kDataset, kPicking };

constexpr std::string_view JobKindName(JobKind kind) {
  switch (kind) {
    case JobKind::kCampaign: return "campaign";
    case JobKind::kModel: return "model";
    case JobKind::kBinFill: return "bin_fill";
    case JobKind::kDataset: return "dataset";
    case JobKind::kPicking: return "picking";
  }
  return "";
}

}  // namespace vscan::service
