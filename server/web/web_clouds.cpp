#include "web/web_clouds.h"

#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "api/job/job_tracker.h"
#include "service/clouds/cloud_store.h"
#include "vscan/common/cloud_io.h"
#include "vscan/common/json_quote.h"
#include "web/web_bytes.h"
#include "web/web_json.h"

namespace vscan::web {
namespace {

// Stored clouds bigger than this are refused (422) rather than parsed for a browser.
constexpr uint64_t kMaxCloudBytes = 1ull << 30;
// Clouds decoded at once: each may take a few hundred MiB while it is parsed and thinned.
constexpr int kMaxConcurrentClouds = 4;
constexpr int kMaxListed = 1000;

std::atomic<int> clouds_in_progress{0};

class CloudSlot {
 public:
  CloudSlot() : held_(clouds_in_progress.fetch_add(1) < kMaxConcurrentClouds) {}
  ~CloudSlot() { clouds_in_progress.fetch_sub(1); }
  bool held() const { return held_; }

 private:
  bool held_;
};

template <typename T>
void AppendPicked(std::string& out, const std::vector<T>& values, const std::vector<uint32_t>& keep) {
  for (const uint32_t i : keep) AppendBytesOf(out, values[i]);
}

std::string FieldList(uint32_t fields) {
  const std::string names = store::FieldNames(fields);
  std::string out = "[";
  size_t start = 0;
  while (start < names.size()) {
    size_t comma = names.find(',', start);
    if (comma == std::string::npos) comma = names.size();
    if (out.size() > 1) out += ',';
    out += JsonQuote(names.substr(start, comma - start));
    start = comma + 1;
  }
  return out + "]";
}

WebReply CloudList(const WebSources& sources, const WebRequest& request) {
  const std::optional<std::string> job = request.Query("job");
  if (job) {
    if (!IsId(*job)) return TextReply(400, fmt::format("job: '{}' is not a job id", *job));
    if (!sources.jobs) return TextReply(404, "jobs are not served");
    auto found = sources.jobs->Get(*job);
    if (!found.ok()) return FromStatus(found.status());
  }
  auto clouds = sources.clouds->List("", kMaxListed, job.value_or(""));
  if (!clouds.ok()) return FromStatus(clouds.status());
  std::string out = "{\"clouds\":[";
  for (size_t i = 0; i < clouds->size(); ++i) {
    if (i) out += ',';
    out += CloudRecordJson((*clouds)[i]);
  }
  return JsonReply(out + "]}");
}

}  // namespace

std::vector<uint32_t> ThinnedIndices(uint64_t total, uint64_t max_points) {
  const uint64_t count = std::min(total, max_points);
  std::vector<uint32_t> keep(count);
  for (uint64_t k = 0; k < count; ++k) {
    // total < 2^32 (a PointCloud's size) and k < count <= total, so the product fits in 64 bits.
    keep[k] = static_cast<uint32_t>(count == total ? k : k * total / count);
  }
  return keep;
}

std::string CloudBinary(const PointCloud& cloud, uint64_t max_points, uint32_t image_width, uint32_t image_height) {
  const std::vector<uint32_t> keep = ThinnedIndices(cloud.size(), max_points);
  const uint32_t fields = cloud.fields | kFieldPosition;
  std::string out;
  PointCloud sizes;
  sizes.fields = fields;
  out.reserve(kCloudHeaderBytes + keep.size() * (sizes.BytesPerPoint() + 4));
  out.append(kCloudMagic, 4);
  AppendBytesOf(out, kCloudLayoutVersion);
  AppendBytesOf(out, fields);
  AppendBytesOf(out, static_cast<uint32_t>(keep.size()));
  AppendBytesOf(out, static_cast<uint64_t>(cloud.size()));
  AppendBytesOf(out, image_width);
  AppendBytesOf(out, image_height);
  AppendPicked(out, cloud.positions, keep);
  if (cloud.Has(kFieldNormal)) AppendPicked(out, cloud.normals, keep);
  if (cloud.Has(kFieldRange)) AppendPicked(out, cloud.ranges, keep);
  if (cloud.Has(kFieldIntensity)) AppendPicked(out, cloud.intensities, keep);
  if (cloud.Has(kFieldInstanceId)) AppendPicked(out, cloud.instance_ids, keep);
  if (cloud.Has(kFieldPixel)) AppendPicked(out, cloud.pixels, keep);
  if (cloud.Has(kFieldCleanPosition)) AppendPicked(out, cloud.clean_positions, keep);
  if (cloud.Has(kFieldIncidence)) AppendPicked(out, cloud.incidence_angles, keep);
  if (cloud.Has(kFieldStatus)) {
    AppendPicked(out, cloud.statuses, keep);
    out.append((4 - keep.size() % 4) % 4, '\0');
  }
  if (cloud.Has(kFieldEstimatedNormal)) AppendPicked(out, cloud.estimated_normals, keep);
  return out;
}

std::string CloudRecordJson(const store::CloudRecord& cloud) {
  std::string out = "{\"cloud_id\":" + JsonQuote(cloud.cloud_id) + ",\"name\":" + JsonQuote(cloud.name) +
                    ",\"points\":" + std::to_string(cloud.points) + ",\"fields\":" + FieldList(cloud.fields) +
                    ",\"origin\":" + (cloud.origin == store::CloudOrigin::kCampaignScan ? "\"campaign_scan\"" : "\"uploaded\"") +
                    ",\"frame\":" + (cloud.frame == store::CloudFrame::kSensor ? "\"sensor\"" : "\"world\"") +
                    ",\"job_id\":" + JsonQuote(cloud.job_id) + ",\"scene_id\":" + JsonQuote(cloud.scene_id) +
                    ",\"world_from_sensor\":";
  if (cloud.world_from_sensor) {
    AppendJsonRows(out, *cloud.world_from_sensor);
  } else {
    out += "null";
  }
  out += ",\"table_angle_deg\":";
  if (cloud.table_angle_deg) {
    AppendJsonNumber(out, *cloud.table_angle_deg);
  } else {
    out += "null";
  }
  out += ",\"camera\":";
  if (cloud.camera) {
    const store::CloudCamera& camera = *cloud.camera;
    out += fmt::format("{{\"width\":{},\"height\":{}", camera.width, camera.height);
    for (const auto& [name, value] : {std::pair{"fx", camera.fx}, {"fy", camera.fy}, {"cx", camera.cx},
                                      {"cy", camera.cy}, {"near", camera.near}, {"far", camera.far}}) {
      out += fmt::format(",\"{}\":", name);
      AppendJsonNumber(out, value);
    }
    out += '}';
  } else {
    out += "null";
  }
  return out + "}";
}

StatusOr<std::string> PlyAsCloudBinary(std::string_view ply, const std::string& name, uint64_t max_points) {
  if (ply.size() > kMaxCloudBytes) {
    return ResourceExhausted(fmt::format("{} has {} bytes; the web view reads clouds of at most {}", name, ply.size(),
                                         kMaxCloudBytes));
  }
  const CloudSlot slot;
  if (!slot.held()) return Unavailable("too many clouds being read at once; try again");
  ASSIGN_OR_RETURN(const PointCloud cloud, ParsePly(ply, name, 4 * kMaxCloudBytes));
  return CloudBinary(cloud, max_points, 0, 0);
}

WebReply ServeClouds(const WebSources& sources, const WebRequest& request) {
  if (!sources.clouds || !sources.blobs) return TextReply(404, "clouds are not served");
  const auto& segments = request.segments;
  if (segments.size() == 1 || (segments.size() == 2 && segments[1].empty())) return CloudList(sources, request);
  if (segments.size() > 3 || !IsId(segments[1]) || (segments.size() == 3 && segments[2] != "record")) {
    return TextReply(404, fmt::format("no cloud '{}'", segments[1]));
  }
  const std::string id(segments[1]);
  if (segments.size() == 3) {
    auto record = sources.clouds->Get(id);
    if (!record.ok()) return FromStatus(record.status());
    return JsonReply(CloudRecordJson(*record));
  }
  auto max_points = QueryInteger(request, "max_points", kDefaultMaxPoints, 1, kMaxMaxPoints);
  if (!max_points.ok()) return FromStatus(max_points.status());
  auto record = sources.clouds->Get(id);
  if (!record.ok()) return FromStatus(record.status());
  if (record->size_bytes > kMaxCloudBytes) {
    return TextReply(422, fmt::format("cloud {} has {} bytes; the web view reads clouds of at most {}", id,
                                      record->size_bytes, kMaxCloudBytes));
  }
  const CloudSlot slot;
  if (!slot.held()) return TextReply(503, "too many clouds being read at once; try again");
  auto stored = service::LoadCloud({*sources.clouds, *sources.blobs}, id);
  if (!stored.ok()) return FromStatus(stored.status());
  auto cloud = ParsePly(stored->ply, stored->record.name, 4 * kMaxCloudBytes);
  if (!cloud.ok()) return FromStatus(cloud.status());
  stored->ply.clear();
  const uint32_t width = stored->record.camera ? stored->record.camera->width : 0;
  const uint32_t height = stored->record.camera ? stored->record.camera->height : 0;
  return {200, kBinaryType, CloudBinary(*cloud, static_cast<uint64_t>(*max_points), width, height), {}};
}

}  // namespace vscan::web
