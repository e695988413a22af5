#include "service/picking/picking_run.h"

#include <cstdio>

#include "service/job/report_writer.h"
#include "service/job/run_end.h"
#include "service/picking/picking_report.h"
#include "vscan/common/cloud_io.h"

namespace vscan::service {
namespace {

constexpr const char* kJsonMediaType = "application/json";
constexpr const char* kPlyMediaType = "application/x-ply";

std::string StepName(size_t step, const char* suffix) {
  char name[48];
  std::snprintf(name, sizeof(name), "step-%03zu%s", step, suffix);
  return name;
}

class PickingRun {
 public:
  PickingRun(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const std::string& name,
             const std::string& bin_job_id, const PickingPlan& plan, jobs::JobControl& control,
             const ClientEstimates* client)
      : context_(context), recorder_(recorder), plan_(plan), control_(control), client_(client) {
    report_.job_id = job_id;
    report_.name = name;
    report_.bin_job_id = bin_job_id;
  }

  void Run() {
    PickingObserver observer;
    observer.perceived = [this](const StepView& view) { Perceived(view); };
    observer.stepped = [this](const picking::PickStep& step, const std::vector<physics::PlacedPart>& pile) {
      Stepped(step, pile);
    };
    if (plan_.perception == Perception::kClient) {
      if (!client_ || !client_->inbox) return Finish(Internal("client perception without an inbox"));
      observer.first_step = client_->first_step ? client_->first_step() : 0;
      observer.client_estimates = [this](const StepView& view) { return ClientEstimatesOf(view); };
    }
    auto result = RunPickingSession(context_, plan_, control_.flag(), observer);
    if (result.ok()) report_.result = std::move(result).value();
    Finish(result.status());
  }

 private:
  void Perceived(const StepView& view) {
    if (report_.truth_artifacts.empty()) report_.parts_at_start = view.truth.size();  // the run's first step
    report_.scan_artifacts.emplace_back();
    report_.truth_artifacts.emplace_back();
    if (!view.scan.positions.empty()) {
      const std::string name = StepName(view.step, ".ply");
      const auto bytes = EncodePly(view.scan);
      if (bytes.ok() && recorder_.RecordArtifact(name, kPlyMediaType, *bytes, nullptr, nullptr,
                                                 Update("step " + std::to_string(view.step) + ": scanned, " +
                                                        std::to_string(view.scan.size()) + " points"))
                            .ok()) {
        report_.scan_artifacts.back() = name;
      }
    }
    const std::string truth = StepName(view.step, "-truth.json");
    if (recorder_.RecordArtifact(truth, kJsonMediaType, recorder_.reports().PickingStepTruthJson(plan_, view), nullptr,
                                 nullptr, Update(TruthMessage(view)))
            .ok()) {
      report_.truth_artifacts.back() = truth;
    }
  }

  // Stored estimates for this pile (a resumed run), else the client's, waited for.
  StatusOr<std::vector<picking::Estimate>> ClientEstimatesOf(const StepView& view) {
    AwaitedStep awaited;
    awaited.step = view.step;
    if (!report_.scan_artifacts.empty()) awaited.scan_artifact = report_.scan_artifacts.back();
    awaited.world_from_sensor = plan_.scan.world_from_sensor;
    for (const physics::PartType& part : plan_.bin.parts) awaited.part_names.push_back(part.name);
    for (const physics::PlacedPart& part : view.truth) awaited.pile.emplace_back(part.type, part.instance);
    awaited.grasps_per_type = view.grasps_per_type;
    if (!view.scan.positions.empty() && awaited.scan_artifact.empty()) {
      return Unavailable("step " + std::to_string(view.step) + ": its scan could not be stored for the client");
    }
    if (client_->stored) {
      if (auto stored = client_->stored(awaited)) {
        (void)recorder_.Record(Update("step " + std::to_string(view.step) + ": " + std::to_string(stored->size()) +
                                      " estimates stored earlier"));
        return std::move(*stored);
      }
    }
    const std::string job_id = report_.job_id;
    client_->inbox->Open(job_id, awaited);
    (void)recorder_.Record(Update("step " + std::to_string(view.step) + ": awaiting estimates"));
    auto estimates = client_->inbox->Wait(job_id, plan_.estimates_timeout, control_.flag());
    if (!estimates.ok() && estimates.status().code() == StatusCode::kDeadlineExceeded) {
      return Status(StatusCode::kDeadlineExceeded, estimates.status().message() + " (spec.estimates_timeout_s)");
    }
    if (estimates.ok()) {
      (void)recorder_.Record(Update("step " + std::to_string(view.step) + ": " + std::to_string(estimates->size()) +
                                    " estimates received"));
    }
    return estimates;
  }

  std::string TruthMessage(const StepView& view) const {
    const std::string step = "step " + std::to_string(view.step) + ": ";
    if (plan_.perception == Perception::kClient) return step + std::to_string(view.truth.size()) + " parts in the pile";
    return step + std::to_string(view.estimates.size()) + " parts found of " + std::to_string(view.truth.size());
  }

  void Stepped(const picking::PickStep& step, const std::vector<physics::PlacedPart>& pile) {
    if (plan_.perception == Perception::kClient && client_->step_done) client_->step_done(step.step);
    if (step.outcome == picking::StepOutcome::kPicked) ++picked_;
    const std::string what = step.outcome == picking::StepOutcome::kPicked
                                 ? "picked " + plan_.bin.parts[step.picked->type].name + "#" +
                                       std::to_string(step.picked->instance + 1)
                                 : std::string(picking::StepOutcomeName(step.outcome)) + ": " + step.detail;
    (void)recorder_.Record(Update("step " + std::to_string(step.step) + ": " + what + "; " +
                                  std::to_string(pile.size()) + " parts left"));
  }

  void Finish(const Status& status) {
    if (report_.result && report_.result->end != "cancelled") {
      const picking::EmptyBinResult& r = *report_.result;
      report_.state = store::JobState::kSucceeded;
      report_.message = r.end + ": " + std::to_string(r.picked) + " of " + std::to_string(report_.parts_at_start) +
                        " parts picked in " + std::to_string(r.steps.size()) + " steps, " +
                        std::to_string(r.fell_out) + " fell out, " + std::to_string(r.pile.size()) + " left";
    } else if (control_.stop_requested()) {
      report_.state = StoppedState(control_.reason());
      report_.message = StoppedMessage(report_.state) + " after " + std::to_string(picked_) +
                        " picks; the scene keeps the pile as the last step left it";
    } else {
      report_.state = store::JobState::kFailed;
      report_.message = status.ok() ? "the run ended without a result" : status.message();
    }
    RecordReport(recorder_, report_.job_id, "picking.json", recorder_.reports().PickingJson(plan_, report_), picked_);
    RecordEnd(recorder_, report_.job_id, Update(report_.message, report_.state));
  }

  JobEventUpdate Update(const std::string& message, store::JobState state = store::JobState::kRunning) const {
    return RunUpdate(message, picked_, state);
  }

  ServiceContext& context_;
  JobRecorder& recorder_;
  const PickingPlan& plan_;
  jobs::JobControl& control_;
  const ClientEstimates* client_;
  uint32_t picked_ = 0;
  PickingJobReport report_;
};

}  // namespace

const char* PerceptionName(Perception perception) {
  switch (perception) {
    case Perception::kTruth: return "truth";
    case Perception::kClient: return "client";
    case Perception::kBaseline: break;
  }
  return "baseline";
}

void RunPicking(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const std::string& name,
                const std::string& bin_job_id, const PickingPlan& plan, jobs::JobControl& control,
                const ClientEstimates* client) {
  PickingRun(context, recorder, job_id, name, bin_job_id, plan, control, client).Run();
}

}  // namespace vscan::service
