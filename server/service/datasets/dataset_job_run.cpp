#include "service/datasets/dataset_job_run.h"

#include <algorithm>
#include <mutex>
#include <set>

#include <spdlog/spdlog.h>

#include "service/job/run_end.h"
#include "service/datasets/format/dataset_merge.h"
#include "service/datasets/dataset_bounds.h"
#include "service/datasets/dataset_job_frames.h"
#include "service/datasets/dataset_space.h"
#include "service/datasets/dataset_job_tar.h"

namespace vscan::service {
namespace {

// "; 2 scenes hold fewer parts than planned (bin full): 3, 7" or nothing.
std::string UnderfilledNote(const dataset::DatasetProgress& progress) {
  if (progress.underfilled.empty()) return "";
  std::string note = "; " + std::to_string(progress.underfilled.size()) +
                     " scenes hold fewer parts than planned (bin full), see their scene_fill.json:";
  for (size_t i = 0; i < progress.underfilled.size() && i < 10; ++i) note += " " + std::to_string(progress.underfilled[i]);
  if (progress.underfilled.size() > 10) note += " ...";
  return note;
}

// The most one scene of the plan writes by the estimate: its largest sensor's views.
uint64_t LargestSceneBytes(const DatasetSetup& setup) {
  uint64_t largest = 0;
  for (const DatasetSensorSetup& sensor : setup.sensors) {
    largest = std::max(largest, DatasetImageBytes(sensor.camera.width, sensor.camera.height));
  }
  return largest * DatasetViewsPerScene(setup.plan);
}

// One writer per dataset directory: a second job resuming the same directory fails at once.
class BusyRoots {
 public:
  bool Claim(const std::filesystem::path& root) {
    std::lock_guard lock(mutex_);
    return roots_.insert(root.string()).second;
  }
  void Release(const std::filesystem::path& root) {
    std::lock_guard lock(mutex_);
    roots_.erase(root.string());
  }

 private:
  std::mutex mutex_;
  std::set<std::string> roots_;
};

BusyRoots& Busy() {
  static BusyRoots busy;
  return busy;
}

class DatasetJobRun {
 public:
  DatasetJobRun(JobRecorder& recorder, const std::string& job_id, const DatasetJob& job, jobs::JobControl& control)
      : recorder_(recorder), job_id_(job_id), job_(job), control_(control), meter_(job.root) {}

  void Run() {
    if (!Busy().Claim(job_.root)) {
      Finish(FailedPrecondition("another job is writing " + job_.root.string()), {});
      return;
    }
    const StatusOr<dataset::DatasetProgress> written = Write();
    Busy().Release(job_.root);
    Finish(written.status(), written.ok() ? *written : last_);
  }

 private:
  StatusOr<dataset::DatasetProgress> Write() {
    const dataset::DatasetPlan& plan = job_.setup->plan;
    RETURN_IF_ERROR(Event("writing " + std::to_string(dataset::SceneCount(plan)) + " scenes into " +
                          job_.root.string()));
    dataset::ShardRun run;
    run.frames_ahead = DatasetFramesAhead();
    bool first = true;
    Status reported = Status::Ok();
    run.on_progress = [&](const dataset::DatasetProgress& progress) {
      last_ = progress;
      if (space_.ok()) space_ = ChargeSpace(first, progress.done < progress.total);
      if (!reported.ok()) return;
      reported = Event(first ? std::to_string(progress.skipped) + " of " + std::to_string(progress.total) +
                                   " scenes already written; " + std::to_string(progress.total - progress.done) +
                                   " to write"
                             : "scene " + std::to_string(progress.done) + " of " + std::to_string(progress.total) +
                                   " written");
      first = false;
    };
    // A failed event (the catalogue) or a full quota stops the run as surely as a cancel.
    run.stop_requested = [&] { return control_.stop_requested() || !reported.ok() || !space_.ok(); };
    std::error_code ec;
    std::filesystem::create_directories(job_.root, ec);
    if (ec) return Internal("cannot create " + job_.root.string() + ": " + ec.message());
    StatusOr<dataset::DatasetProgress> progress = dataset::RunDatasetShard(
        job_.root, plan, job_.setup->parts, BinFrameSource(job_.setup, control_.flag()), run);
    RETURN_IF_ERROR(reported);
    RETURN_IF_ERROR(space_);
    if (!progress.ok()) return progress.status();
    RETURN_IF_ERROR(dataset::MergeDataset(job_.root, plan));
    RETURN_IF_ERROR(Event("every scene checked; scenes.json written"));
    // The tar is as large as the directory: checked before it is built in memory.
    RETURN_IF_ERROR(ChargeTar());
    StatusOr<std::string> tar = TarDirectory(job_.root, job_.max_tar_bytes, control_.flag());
    if (!tar.ok()) {
      if (tar.status().code() == StatusCode::kCancelled) return tar.status();
      spdlog::warn("job {}: no dataset.tar: {}", job_id_, tar.status().ToString());
      return progress;
    }
    RETURN_IF_ERROR(recorder_.RecordArtifact("dataset.tar", "application/x-tar", *tar, nullptr, nullptr,
                                             Update("dataset.tar stored"))
                        .status());
    return progress;
  }

  // The directory as measured now, and room for the next scene when one follows.
  Status ChargeSpace(bool whole, bool more) {
    if (!job_.directories) return Status::Ok();
    const StatusOr<uint64_t> bytes = whole ? meter_.MeasureAll() : meter_.MeasureNewScenes();
    if (!bytes.ok()) {
      spdlog::warn("job {}: {}", job_id_, bytes.status().ToString());
      return Status::Ok();
    }
    const Status room = job_.directories->Charge(job_.directory_id, *bytes, more ? LargestSceneBytes(*job_.setup) : 0,
                                                 "the dataset's next scene");
    if (room.ok() || !more) return Status::Ok();
    return ResourceExhausted(room.message() + "; the scenes written stay in " + job_.root.string() +
                             ": free space, then resume the job");
  }

  Status ChargeTar() {
    if (!job_.directories) return Status::Ok();
    const StatusOr<uint64_t> bytes = meter_.MeasureAll();
    if (!bytes.ok() || *bytes > job_.max_tar_bytes) return Status::Ok();
    const Status room = job_.directories->Charge(job_.directory_id, *bytes, *bytes, "dataset.tar");
    if (room.ok()) return Status::Ok();
    return ResourceExhausted(room.message() + "; every scene is written in " + job_.root.string() +
                             ": free space, then resume the job for its tar");
  }

  void Finish(const Status& status, const dataset::DatasetProgress& progress) {
    store::JobState state = store::JobState::kSucceeded;
    std::string message;
    if (status.ok()) {
      message = std::to_string(progress.total) + " scenes in " + job_.root.string() + " (" +
                std::to_string(progress.written) + " written, " + std::to_string(progress.skipped) +
                " found finished)" + UnderfilledNote(progress);
    } else if (control_.stop_requested()) {
      state = StoppedState(control_.reason());
      message = StoppedMessage(state) + " after " + std::to_string(progress.done) + " of " + std::to_string(progress.total) +
                " scenes; they stay in " + job_.root.string();
    } else {
      state = store::JobState::kFailed;
      message = status.code() == StatusCode::kResourceExhausted ? status.ToString() : status.message();
    }
    steps_done_ = static_cast<uint32_t>(progress.done);
    RecordEnd(recorder_, job_id_, Update(message, state));
  }

  JobEventUpdate Update(const std::string& message, store::JobState state = store::JobState::kRunning) const {
    JobEventUpdate update;
    update.state = state;
    update.message = message;
    update.steps_done = steps_done_;
    return update;
  }

  Status Event(const std::string& message) {
    steps_done_ = static_cast<uint32_t>(last_.done);
    return recorder_.Record(Update(message));
  }

  JobRecorder& recorder_;
  const std::string job_id_;
  const DatasetJob& job_;
  jobs::JobControl& control_;
  dataset::DatasetProgress last_;
  DatasetSpaceMeter meter_;
  Status space_ = Status::Ok();
  uint32_t steps_done_ = 0;
};

}  // namespace

std::filesystem::path DatasetJobRoot(const std::string& data_dir, const std::string& directory_job_id) {
  return std::filesystem::path(data_dir) / "datasets" / directory_job_id;
}

void RunDatasetJob(JobRecorder& recorder, const std::string& job_id, const DatasetJob& job, jobs::JobControl& control) {
  DatasetJobRun(recorder, job_id, job, control).Run();
}

}  // namespace vscan::service
