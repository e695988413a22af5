#include "web/web_jobs.h"

#include <string>

#include <fmt/format.h>
#include <google/protobuf/util/json_util.h>

#include "api/job/job_tracker.h"
#include "store/blob_reader.h"
#include "store/sqlite_statement.h"
#include "store/stored_enums.h"
#include "vscan/common/json_quote.h"
#include "web/web_clouds.h"
#include "web/web_job_sensor.h"

namespace vscan::web {
namespace {

constexpr const char* kEventStreamType = "text/event-stream";

std::string ToJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string out;
  if (!google::protobuf::util::MessageToJsonString(message, &out, options).ok()) return "{}";
  return out;
}

// The catalogue lists jobs by id (random); the page wants the newest, so the rows are read here
// newest first, LIMIT bounding the answer.
WebReply JobList(api::JobTracker& tracker, const WebRequest& request) {
  auto limit = QueryInteger(request, "limit", 50, 1, kMaxListedJobs);
  if (!limit.ok()) return FromStatus(limit.status());
  store::Database& database = tracker.catalogue().database();
  std::string out = "{\"jobs\":[";
  std::lock_guard lock(database.mutex());
  const Status read = store::sqlite::InTransaction(database.handle(), false, [&]() -> Status {
    ASSIGN_OR_RETURN(store::sqlite::Statement s,
                     store::sqlite::Statement::Prepare(
                         database.handle(),
                         "SELECT job_id, kind, state, name, message, steps_done, steps_total, create_time_ms "
                         "FROM jobs ORDER BY create_time_ms DESC, job_id DESC LIMIT ?1"));
    s.Bind(1, static_cast<int64_t>(*limit));
    bool first = true;
    for (;;) {
      ASSIGN_OR_RETURN(const bool row, s.Step());
      if (!row) break;
      const std::optional<store::JobState> state = store::kJobStateCodes.Backward(s.Int(2));
      out += first ? "" : ",";
      first = false;
      out += fmt::format(
          "{{\"job_id\":{},\"kind\":{},\"state\":{},\"name\":{},\"message\":{},\"steps_done\":{},\"steps_total\":{},"
          "\"create_time_ms\":{}}}",
          JsonQuote(s.Text(0)), JsonQuote(s.Text(1)), JsonQuote(state ? store::JobStateName(*state) : "UNKNOWN"),
          JsonQuote(s.Text(3)), JsonQuote(s.Text(4)), s.Int(5), s.Int(6), s.Int(7));
    }
    return Status::Ok();
  });
  if (!read.ok()) return FromStatus(read);
  return JsonReply(out + "]}");
}

WebReply Artifact(api::JobTracker& tracker, const std::string& job_id, const std::string& artifact_id,
                  const WebRequest& request) {
  const std::optional<std::string> as = request.Query("as");
  if (as && *as != "cloud") return TextReply(400, fmt::format("as: '{}' is not 'cloud' (or absent: the bytes)", *as));
  auto max_points = QueryInteger(request, "max_points", kDefaultMaxPoints, 1, kMaxMaxPoints);
  if (!max_points.ok()) return FromStatus(max_points.status());
  auto record = tracker.catalogue().GetArtifact(job_id, artifact_id);
  if (!record.ok()) return FromStatus(record.status());
  if (as && record->media_type != "model/ply") {
    return TextReply(400, fmt::format("as: artifact {} is {}, not a PLY cloud", record->name, record->media_type));
  }
  if (record->size_bytes > kMaxArtifactBytes) {
    return TextReply(422, fmt::format("artifact {} has {} bytes; the web view sends at most {}", record->name,
                                      record->size_bytes, kMaxArtifactBytes));
  }
  if (!as) {
    // Sent a chunk at a time, so that a large artifact is never whole in memory.
    auto reader = tracker.blobs().OpenReader(record->sha256);
    if (!reader.ok()) return FromStatus(reader.status());
    auto shared = std::make_shared<store::BlobReader>(std::move(reader).value());
    WebReply reply{200, record->media_type, {}, {}};
    reply.stream_length = static_cast<long long>(shared->size());
    reply.stream = [shared](const WebWrite& write) {
      constexpr size_t kChunk = 1 << 20;
      for (uint64_t offset = 0; offset < shared->size(); offset += kChunk) {
        auto chunk = shared->Read(offset, kChunk);
        if (!chunk.ok() || !write(*chunk)) return;
      }
    };
    return reply;
  }
  auto bytes = tracker.blobs().Get(record->sha256);
  if (!bytes.ok()) return FromStatus(bytes.status());
  auto cloud = PlyAsCloudBinary(*bytes, record->name, static_cast<uint64_t>(*max_points));
  if (!cloud.ok() && cloud.status().code() == StatusCode::kUnavailable) return TextReply(503, cloud.status().message());
  if (!cloud.ok()) return FromStatus(cloud.status());
  return {200, kBinaryType, std::move(cloud).value(), {}};
}

// Follows one live job for a stream: poked by the tracker after each event and by Stop.
class StreamWatcher final : public api::JobWatcher, public JobStreams::Waker {
 public:
  void OnJobEvent() override { Wake(); }
  void Wake() override {
    {
      std::lock_guard lock(mutex_);
      ++pokes_;
    }
    poked_.notify_all();
  }
  uint64_t pokes() {
    std::lock_guard lock(mutex_);
    return pokes_;
  }
  // Returns once poked after seen, stopping, or at deadline.
  void WaitPast(uint64_t seen, std::chrono::steady_clock::time_point deadline, const JobStreams& streams) {
    std::unique_lock lock(mutex_);
    poked_.wait_until(lock, deadline, [&] { return pokes_ != seen || streams.stopped(); });
  }

 private:
  ~StreamWatcher() override = default;
  std::mutex mutex_;
  std::condition_variable poked_;
  uint64_t pokes_ = 0;
};

std::string DataLine(const google::protobuf::Message& message) { return "data: " + ToJson(message) + "\n\n"; }

// The snapshot, then each event as it happens, until the job ends, the client goes or the view stops.
void StreamEvents(api::JobTracker& tracker, JobStreams& streams, const std::string& job_id, const WebWrite& write) {
  auto* watcher = new StreamWatcher();
  streams.Watch(watcher);
  std::shared_ptr<api::LiveJob> live = tracker.Live(job_id);
  uint64_t next = 1;
  v1::WatchJobResponse first;
  if (live) {
    *first.mutable_job() = live->Attach(watcher, &next);
  } else if (auto job = tracker.Get(job_id); job.ok()) {
    *first.mutable_job() = std::move(job).value();
  }
  bool open = write(DataLine(first));
  auto last_write = std::chrono::steady_clock::now();
  bool ended = !live;
  while (open && live && !streams.stopped()) {
    const uint64_t seen = watcher->pokes();
    v1::WatchJobResponse response;
    const api::LiveJob::Next got = live->Get(watcher, next, &response);
    if (got == api::LiveJob::Next::kReady) {
      ++next;
      open = write(DataLine(response));
      last_write = std::chrono::steady_clock::now();
      continue;
    }
    if (got == api::LiveJob::Next::kEnded) {
      ended = true;
      break;
    }
    watcher->WaitPast(seen, last_write + streams.keep_alive(), streams);
    if (!streams.stopped() && std::chrono::steady_clock::now() >= last_write + streams.keep_alive()) {
      open = write(": keep-alive\n\n");
      last_write = std::chrono::steady_clock::now();
    }
  }
  // Tells the page the job ended (a plain close may be the view stopping).
  if (open && ended) write("event: end\ndata: {}\n\n");
  if (live) live->Detach(watcher);
  streams.Unwatch(watcher);
  watcher->Unref();
}

WebReply Events(api::JobTracker& tracker, const std::shared_ptr<JobStreams>& streams, const std::string& job_id) {
  // The job must exist before the stream's headers go out.
  if (auto job = tracker.Get(job_id); !job.ok()) return FromStatus(job.status());
  if (!streams->Enter()) {
    return TextReply(503, streams->stopped() ? "the web view is stopping" : "too many event streams open; try again later");
  }
  // The slot is left when the stream ends, or when the reply is dropped unsent.
  auto slot = std::shared_ptr<JobStreams>(streams.get(), [keep = streams](JobStreams* s) { s->Leave(); });
  WebReply reply{200, kEventStreamType, {}, {}};
  reply.stream = [&tracker, slot, job_id](const WebWrite& write) { StreamEvents(tracker, *slot, job_id, write); };
  return reply;
}

}  // namespace

void JobStreams::Stop() {
  std::lock_guard lock(mutex_);
  stopped_ = true;
  for (Waker* waker : wakers_) waker->Wake();
}

int JobStreams::open() const {
  std::lock_guard lock(mutex_);
  return open_;
}

bool JobStreams::Enter() {
  std::lock_guard lock(mutex_);
  if (stopped_ || open_ >= max_streams_) return false;
  ++open_;
  return true;
}

void JobStreams::Leave() {
  std::lock_guard lock(mutex_);
  --open_;
}

void JobStreams::Watch(Waker* waker) {
  std::lock_guard lock(mutex_);
  wakers_.insert(waker);
}

void JobStreams::Unwatch(Waker* waker) {
  std::lock_guard lock(mutex_);
  wakers_.erase(waker);
}

WebReply ServeJobs(const WebSources& sources, const std::shared_ptr<JobStreams>& streams, const WebRequest& request) {
  if (!sources.jobs) return TextReply(404, "jobs are not served");
  api::JobTracker& tracker = *sources.jobs;
  const auto& segments = request.segments;
  if (segments.size() == 1 || (segments.size() == 2 && segments[1].empty())) return JobList(tracker, request);
  if (!IsId(segments[1])) return TextReply(404, fmt::format("no job '{}'", segments[1]));
  const std::string job_id(segments[1]);
  if (segments.size() == 2) {
    auto job = tracker.Get(job_id);
    if (!job.ok()) return FromStatus(job.status());
    return JsonReply(ToJson(*job));
  }
  if (segments.size() == 3 && segments[2] == "events") return Events(tracker, streams, job_id);
  if (segments.size() == 3 && segments[2] == "sensor") return JobSensor(tracker, job_id);
  if (segments.size() == 4 && segments[2] == "artifacts" && IsId(segments[3])) {
    return Artifact(tracker, job_id, std::string(segments[3]), request);
  }
  return TextReply(404, fmt::format("no such resource under job '{}'", job_id));
}

}  // namespace vscan::web
