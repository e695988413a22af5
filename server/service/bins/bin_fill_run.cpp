#include "service/bins/bin_fill_run.h"

#include <algorithm>
#include <cstdio>

#include <spdlog/spdlog.h>

#include "service/bins/bin_fill_report.h"
#include "service/bins/bin_fill_simulation.h"
#include "service/bins/bin_scene.h"
#include "service/job/run_end.h"
#include "service/job/message_numbers.h"

namespace vscan::service {
namespace {

constexpr const char* kJsonMediaType = "application/json";
constexpr const char* kBinaryMediaType = "application/octet-stream";

class BinFillRun {
 public:
  BinFillRun(scenes::SceneRegistry& registry, JobRecorder& recorder, const std::string& job_id, const BinFillPlan& plan,
             jobs::JobControl& control)
      : registry_(registry), recorder_(recorder), plan_(plan), control_(control), total_(plan.parts_total()) {
    report_.job_id = job_id;
  }

  void Run() {
    const physics::BinSpec& bin = plan_.request.bin;
    const physics::BinInterior interior = physics::InteriorOf(bin);
    const Eigen::Vector3d size = interior.hi - interior.lo;
    const std::string what = plan_.request.mesh_bin ? "the mesh bin " + plan_.request.bin_mesh_id + " (bounding box "
                                                    : "a bin of ";
    Status status = Event("filling " + what + Rounded(size.x()) + " x " + Rounded(size.y()) + " x " + Rounded(size.z()) +
                          (plan_.request.mesh_bin ? " m)" : " m") + " with " + std::to_string(total_) + " parts of " +
                          std::to_string(plan_.parts.size()) + " types");
    if (status.ok()) status = Fill();
    Finish(status);
  }

 private:
  Status Fill() {
    Status observed = Status::Ok();
    report_.result = SimulateBinFill(plan_, control_.flag(), [&](const FillProgress& progress) {
      if (!observed.ok()) return;
      steps_done_ = static_cast<uint32_t>(std::min<uint64_t>(progress.dropped, total_));
      observed = Event(Rounded(progress.simulated_s) + " s simulated: " + std::to_string(progress.dropped) + " of " +
                       std::to_string(total_) + " parts dropped, " + std::to_string(progress.slow) + " resting, " +
                       std::to_string(progress.removed) + " out of the bin");
    }, &replay_);
    RETURN_IF_ERROR(observed);
    steps_done_ = static_cast<uint32_t>(report_.result->spawned);
    // A stop asked after the physics ended still wins: nothing has touched the scene yet.
    if (control_.stop_requested() || report_.result->end == physics::FillEnd::kCancelled) return Status::Ok();
    auto placement = PlaceBinInScene(registry_, plan_, *report_.result);
    if (!placement.ok()) {
      return Status(placement.status().code(), "the settled parts could not be placed in scene '" +
                                                   plan_.request.scene_id + "': " + placement.status().message());
    }
    report_.placement = std::move(placement).value();
    if (plan_.pick_check) return CheckPicks();
    return Status::Ok();
  }

  // The placed parts (and only they: no other object of the scene) checked for picks.
  Status CheckPicks() {
    const BinPlacement& placement = *report_.placement;
    std::vector<std::string> part_object_ids;
    for (const store::ObjectRecord& part : placement.parts) part_object_ids.push_back(part.object_id);
    RETURN_IF_ERROR(Event("checking picks of " + std::to_string(placement.parts.size()) + " parts"));
    auto picks = plan_.pick_check(part_object_ids, control_.flag());
    if (!picks.ok()) {
      return Status(picks.status().code(), "scene revision " + std::to_string(placement.revision) +
                                               " holds the settled parts; the pick check did not finish: " +
                                               picks.status().message());
    }
    report_.picks = std::move(picks).value();
    return Status::Ok();
  }

  std::string PicksSummary() const {
    if (!report_.picks) return "";
    size_t pickable = 0;
    for (const BinPartPick& part : report_.picks->parts) pickable += part.verdict.pickable ? 1 : 0;
    return "; " + std::to_string(pickable) + " of " + std::to_string(report_.picks->parts.size()) +
           " parts pickable";
  }

  void Finish(const Status& status) {
    if (report_.placement && !status.ok()) {
      // Placed, but the pick check did not finish: the scene keeps the parts.
      report_.state = control_.stop_requested() ? StoppedState(control_.reason()) : store::JobState::kFailed;
      report_.message = status.message();
    } else if (report_.placement) {
      const physics::FillResult& result = *report_.result;
      report_.state = store::JobState::kSucceeded;
      report_.message = std::string(physics::FillEndName(result.end)) + ": " + std::to_string(result.parts.size()) +
                        " parts in the bin, " + std::to_string(result.outside.size()) + " out of it, " +
                        Rounded(result.simulated_s) + " s simulated; scene revision " +
                        std::to_string(report_.placement->revision) + " (" + result.message + ")" + PicksSummary();
    } else if (control_.stop_requested()) {
      report_.state = StoppedState(control_.reason());
      report_.message = StoppedMessage(report_.state) + "; the scene is unchanged";
    } else {
      report_.state = store::JobState::kFailed;
      report_.message = status.ok() ? "the fill ended without placing its parts" : status.message();
    }
    // The replay goes with bin.json's parts: whenever the physics ran, however the fill ended.
    if (report_.result) {
      const auto replay = recorder_.RecordArtifact("bin_replay.bin", kBinaryMediaType, EncodeBinReplay(replay_), nullptr,
                                                   nullptr, Update("bin_replay.bin written"));
      if (!replay.ok()) spdlog::warn("job {}: bin_replay.bin not stored: {}", report_.job_id, replay.status().ToString());
    }
    const std::string json = recorder_.reports().BinFillJson(plan_, report_);
    const auto stored = recorder_.RecordArtifact("bin.json", kJsonMediaType, json, nullptr, nullptr,
                                                 Update("bin.json written"));
    if (!stored.ok()) spdlog::warn("job {}: bin.json not stored: {}", report_.job_id, stored.status().ToString());
    RecordEnd(recorder_, report_.job_id, Update(report_.message, report_.state));
  }

  JobEventUpdate Update(const std::string& message, store::JobState state = store::JobState::kRunning) const {
    JobEventUpdate update;
    update.state = state;
    update.message = message;
    update.steps_done = steps_done_;
    return update;
  }

  Status Event(const std::string& message) { return recorder_.Record(Update(message)); }

  scenes::SceneRegistry& registry_;
  JobRecorder& recorder_;
  const BinFillPlan& plan_;
  jobs::JobControl& control_;
  const size_t total_;
  uint32_t steps_done_ = 0;
  BinFillReport report_;
  BinReplay replay_;
};

}  // namespace

void RunBinFill(scenes::SceneRegistry& registry, JobRecorder& recorder, const std::string& job_id, const BinFillPlan& plan,
                jobs::JobControl& control) {
  BinFillRun(registry, recorder, job_id, plan, control).Run();
}

}  // namespace vscan::service
