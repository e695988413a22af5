#include "api/picking/picking_estimates_files.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

#include <spdlog/spdlog.h>

#include "service/datasets/format/durable_file.h"
#include "vscan/common/pose.h"
#include "vscan/common/report_json.h"

namespace vscan::api {
namespace {

std::string EstimatesName(size_t step) {
  char name[48];
  std::snprintf(name, sizeof(name), "step-%03zu-estimates.json", step);
  return name;
}

// A replacement that a crash leaves either old or new, never half written.
Status ReplaceDurably(const std::filesystem::path& path, const std::string& bytes) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  if (ec) return Unavailable("cannot create '" + path.parent_path().string() + "': " + ec.message());
  return service::dataset::ReplaceFileDurably(path, bytes, ".tmp");
}

}  // namespace

PickingEstimatesFiles::PickingEstimatesFiles(const std::filesystem::path& data_dir, const std::string& job_id)
    : dir_(DirectoryOf(data_dir, job_id)) {}

std::filesystem::path PickingEstimatesFiles::DirectoryOf(const std::filesystem::path& data_dir,
                                                         const std::string& job_id) {
  return data_dir / "picking" / job_id;
}

Status PickingEstimatesFiles::Write(const v1::PickingStepTruth& estimates) const {
  return ReplaceDurably(dir_ / EstimatesName(estimates.step()), PrintReport(estimates));
}

std::optional<v1::PickingStepTruth> PickingEstimatesFiles::Read(size_t step) const {
  const std::filesystem::path path = dir_ / EstimatesName(step);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  auto text = service::dataset::ReadWholeFile(path);
  v1::PickingStepTruth out;
  if (!text.ok() || !ParseReport(*text, path.string(), &out).ok() || out.step() != step) {
    spdlog::warn("{}: unreadable, the step waits for estimates again", path.string());
    return std::nullopt;
  }
  return out;
}

size_t PickingEstimatesFiles::FirstStep() const {
  std::ifstream in(dir_ / "steps-done");
  size_t done = 0;
  if (in >> done) return done;
  return 0;
}

Status PickingEstimatesFiles::MarkDone(size_t step) const {
  return ReplaceDurably(dir_ / "steps-done", std::to_string(step + 1) + "\n");
}

std::optional<std::vector<picking::Estimate>> StoredEstimatesFor(const v1::PickingStepTruth& stored,
                                                                 const service::AwaitedStep& awaited) {
  std::map<std::string, size_t> type_of;
  for (size_t t = 0; t < awaited.part_names.size(); ++t) type_of.emplace(awaited.part_names[t], t);
  std::set<std::pair<size_t, size_t>> pile;
  for (const v1::PickingPose& part : stored.parts()) {
    const auto type = type_of.find(part.part());
    if (type == type_of.end()) return std::nullopt;
    pile.emplace(type->second, part.instance());
  }
  if (pile != std::set<std::pair<size_t, size_t>>(awaited.pile.begin(), awaited.pile.end())) return std::nullopt;
  std::vector<picking::Estimate> out;
  for (const v1::PickingPose& estimate : stored.estimates()) {
    const auto type = type_of.find(estimate.part());
    if (type == type_of.end() || estimate.world_from_part_size() != 16) return std::nullopt;
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = estimate.world_from_part(r * 4 + c);
    auto pose = PoseFromMatrix(m, "world_from_part");
    if (!pose.ok() || !std::isfinite(estimate.score())) return std::nullopt;
    out.push_back({type->second, *pose, estimate.score()});
  }
  return out;
}

service::ClientEstimates ClientEstimatesOver(std::shared_ptr<const PickingEstimatesFiles> files,
                                             service::EstimatesInbox& inbox) {
  service::ClientEstimates client;
  client.inbox = &inbox;
  client.first_step = [files] { return files->FirstStep(); };
  client.stored = [files](const service::AwaitedStep& awaited) -> std::optional<std::vector<picking::Estimate>> {
    const auto stored = files->Read(awaited.step);
    if (!stored) return std::nullopt;
    return StoredEstimatesFor(*stored, awaited);
  };
  client.step_done = [files](size_t step) {
    const Status marked = files->MarkDone(step);
    if (!marked.ok()) spdlog::warn("picking: step {} not marked done: {}", step, marked.ToString());
  };
  return client;
}

}  // namespace vscan::api
