#include "api/job/job_kinds.h"

#include <array>

namespace vscan::api {
namespace {

using service::JobKind;

constexpr std::array<JobKindRow, 5> kJobKinds{{
    {JobKind::kCampaign, "campaign spec",
     [](const std::string& bytes, v1::Job* out) { return out->mutable_campaign()->ParseFromString(bytes); }},
    {JobKind::kModel, "model spec",
     [](const std::string& bytes, v1::Job* out) { return out->mutable_model()->ParseFromString(bytes); }},
    {JobKind::kBinFill, "bin fill spec",
     [](const std::string& bytes, v1::Job* out) { return out->mutable_bin_fill()->ParseFromString(bytes); }},
    {JobKind::kDataset, "dataset spec",
     [](const std::string& bytes, v1::Job* out) { return out->mutable_dataset()->ParseFromString(bytes); }},
    {JobKind::kPicking, "picking spec",
     [](const std::string& bytes, v1::Job* out) { return out->mutable_picking()->ParseFromString(bytes); }},
}};

}  // namespace

const JobKindRow* FindJobKind(std::string_view name) {
  for (const JobKindRow& row : kJobKinds) {
    if (service::JobKindName(row.kind) == name) return &row;
  }
  return nullptr;
}

}  // namespace vscan::api
