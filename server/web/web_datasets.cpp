#include "web/web_datasets.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <optional>

#include <fmt/format.h>

#include "api/datasets/dataset_spec.h"
#include "api/job/job_tracker.h"
#include "service/datasets/dataset_directories.h"
#include "service/datasets/format/dataset_layout.h"
#include "service/job/job_kind.h"
#include "store/job_catalogue.h"
#include "vscan/common/json_quote.h"
#include "web/web_api.h"
#include "web/web_dataset_json.h"

namespace vscan::web {
namespace {

namespace fs = std::filesystem;
namespace layout = service::dataset;

constexpr size_t kMaxPathBytes = 256;
constexpr size_t kMaxPathParts = 8;
constexpr size_t kMaxPartBytes = 64;
// Dataset jobs /api/datasets lists, newest first.
constexpr size_t kMaxDatasetsListed = 1000;
// Scenes /api/datasets/{id} lists at once (?limit, ?after page through the rest).
constexpr long long kMaxScenesListed = 1000;
constexpr long long kMaxSceneId = 999'999;
constexpr long long kMaxViewId = 999;

constexpr std::pair<std::string_view, std::string_view> kFileTypes[] = {
    {"png", "image/png"}, {"json", "application/json"}, {"ply", "application/octet-stream"}};

bool IsWordChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

bool IsWord(std::string_view part) {
  return !part.empty() && part.size() <= kMaxPartBytes && std::all_of(part.begin(), part.end(), IsWordChar);
}

// "000042" and the like: n digits exactly.
bool IsDigits(std::string_view text, size_t n) {
  return text.size() == n && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// A closing fd.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

Status OpenFailure(std::string_view path, int error) {
  if (error == ENOENT || error == ELOOP || error == ENOTDIR || error == EACCES) {
    return NotFound(fmt::format("no file '{}' in the dataset", path));
  }
  return Internal(fmt::format("cannot open '{}': {}", path, std::strerror(error)));
}

// A directory entry that is itself a directory, not a link to one.
bool IsRealDirectory(const fs::directory_entry& entry) {
  std::error_code ec;
  return entry.symlink_status(ec).type() == fs::file_type::directory && !ec;
}

bool IsRealDirectory(const fs::path& path) {
  std::error_code ec;
  return fs::symlink_status(path, ec).type() == fs::file_type::directory && !ec;
}

// The complete scenes of a dataset root: train_pbr/<six digits>, never <six digits>.partial.
std::vector<uint64_t> CompleteScenes(const fs::path& root) {
  std::vector<uint64_t> scenes;
  const fs::path split = root / layout::kScenesDir;
  if (!IsRealDirectory(root) || !IsRealDirectory(split)) return scenes;
  std::error_code ec;
  for (auto it = fs::directory_iterator(split, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (IsDigits(name, 6) && IsRealDirectory(*it)) scenes.push_back(std::stoull(name));
  }
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

// The views of a complete scene: depth/<six digits>.png, which every view has.
std::vector<uint64_t> SceneViews(const fs::path& scene_dir) {
  std::vector<uint64_t> views;
  std::error_code ec;
  for (auto it = fs::directory_iterator(scene_dir / "depth", ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() == 10 && name.ends_with(".png") && IsDigits(std::string_view(name).substr(0, 6), 6)) {
      views.push_back(std::stoull(name.substr(0, 6)));
    }
  }
  std::sort(views.begin(), views.end());
  return views;
}

struct DatasetJob {
  store::JobRecord job;
  fs::path root;
};

StatusOr<DatasetJob> FindDatasetJob(const WebSources& sources, std::string_view job_id) {
  if (!IsId(job_id)) return NotFound(fmt::format("no dataset job '{}'", job_id));
  auto job = sources.jobs->catalogue().GetJob(std::string(job_id));
  if (!job.ok()) {
    if (job.status().code() == StatusCode::kNotFound) return NotFound(fmt::format("no dataset job '{}'", job_id));
    return job.status();
  }
  if (job->kind != service::JobKindName(service::JobKind::kDataset)) {
    return NotFound(fmt::format("job '{}' is a {} job, not a dataset job", job_id, job->kind));
  }
  const std::string directory = api::DatasetDirectoryOf(*job);
  if (!service::IsDatasetDirectoryName(directory)) {
    return NotFound(fmt::format("dataset job '{}' names no directory", job_id));
  }
  DatasetJob found{std::move(job).value(), sources.datasets->Root(directory)};
  return found;
}

// dataset.json, or nullopt while the job has not written it.
std::optional<JsonValue> Manifest(const fs::path& root) {
  auto bytes = ReadDatasetFile(root, layout::kManifestFile, kMaxDatasetFileBytes);
  if (!bytes.ok()) return std::nullopt;
  auto manifest = ParseJson(*bytes, layout::kManifestFile);
  if (!manifest.ok()) return std::nullopt;
  return std::move(manifest).value();
}

void AppendNumberOrNull(std::string& out, const JsonValue* value) {
  if (value && value->IsNumber()) {
    AppendJson(out, *value);
  } else {
    out += "null";
  }
}

// "job_id","name","state","message","directory_id","scene_count","scenes_complete" (no braces).
void AppendJobFields(std::string& out, const DatasetJob& dataset, const std::optional<JsonValue>& manifest,
                     size_t scenes_complete) {
  out += fmt::format("\"job_id\":{},\"name\":{},\"state\":{},\"message\":{},\"directory_id\":{},\"scene_count\":",
                     JsonQuote(dataset.job.job_id), JsonQuote(dataset.job.name),
                     JsonQuote(store::JobStateName(dataset.job.state)), JsonQuote(dataset.job.message),
                     JsonQuote(dataset.root.filename().string()));
  AppendNumberOrNull(out, manifest ? manifest->Find("scene_count") : nullptr);
  out += fmt::format(",\"scenes_complete\":{}", scenes_complete);
}

WebReply List(const WebSources& sources) {
  auto jobs = sources.jobs->catalogue().ListJobsOfKind(std::string(service::JobKindName(service::JobKind::kDataset)));
  if (!jobs.ok()) return FromStatus(jobs.status());
  std::stable_sort(jobs->begin(), jobs->end(),
                   [](const auto& a, const auto& b) { return a.create_time_ms > b.create_time_ms; });
  if (jobs->size() > kMaxDatasetsListed) jobs->resize(kMaxDatasetsListed);
  std::string out = "{\"datasets\":[";
  bool first = true;
  for (store::JobRecord& job : *jobs) {
    const std::string directory = api::DatasetDirectoryOf(job);
    if (!service::IsDatasetDirectoryName(directory)) continue;
    DatasetJob dataset{std::move(job), sources.datasets->Root(directory)};
    if (!first) out += ',';
    first = false;
    out += '{';
    AppendJobFields(out, dataset, Manifest(dataset.root), CompleteScenes(dataset.root).size());
    out += '}';
  }
  out += "]}";
  return JsonReply(std::move(out));
}

WebReply Dataset(const WebRequest& request, const DatasetJob& dataset) {
  const auto after = QueryInteger(request, "after", -1, -1, kMaxSceneId);
  if (!after.ok()) return FromStatus(after.status());
  const auto limit = QueryInteger(request, "limit", kMaxScenesListed, 1, kMaxScenesListed);
  if (!limit.ok()) return FromStatus(limit.status());
  const std::optional<JsonValue> manifest = Manifest(dataset.root);
  const std::vector<uint64_t> scenes = CompleteScenes(dataset.root);
  std::string out = "{";
  AppendJobFields(out, dataset, manifest, scenes.size());
  const JsonValue* plan = manifest ? manifest->Find("plan") : nullptr;
  out += ",\"depth_scale_mm\":";
  AppendNumberOrNull(out, plan ? plan->Find("depth_scale_mm") : nullptr);
  out += ",\"models\":[";
  std::vector<uint64_t> models;
  std::error_code ec;
  if (IsRealDirectory(dataset.root / layout::kModelsDir)) {
    for (auto it = fs::directory_iterator(dataset.root / layout::kModelsDir, ec);
         !ec && it != fs::directory_iterator(); it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (name.size() == 14 && name.starts_with("obj_") && name.ends_with(".ply") &&
          IsDigits(std::string_view(name).substr(4, 6), 6)) {
        models.push_back(std::stoull(name.substr(4, 6)));
      }
    }
  }
  std::sort(models.begin(), models.end());
  for (size_t i = 0; i < models.size(); ++i) {
    out += fmt::format("{}{{\"obj_id\":{},\"file\":\"{}/obj_{}.ply\"}}", i ? "," : "", models[i], layout::kModelsDir,
                       layout::SixDigits(models[i]));
  }
  out += fmt::format("],\"splits\":[{{\"split\":\"{}\",\"scenes\":[", layout::kScenesDir);
  auto begin = std::upper_bound(scenes.begin(), scenes.end(), *after, [](long long a, uint64_t b) {
    return a < static_cast<long long>(b);
  });
  const auto end = scenes.end() - begin > *limit ? begin + *limit : scenes.end();
  for (auto it = begin; it != end; ++it) {
    const std::string scene_id = layout::SixDigits(*it);
    out += fmt::format("{}{{\"scene_id\":\"{}\",\"views\":[", it == begin ? "" : ",", scene_id);
    const std::vector<uint64_t> views = SceneViews(layout::SceneDir(dataset.root, *it));
    for (size_t v = 0; v < views.size(); ++v) out += fmt::format("{}{}", v ? "," : "", views[v]);
    out += "]}";
  }
  out += fmt::format("],\"more\":{}}}]}}", end != scenes.end() ? "true" : "false");
  return JsonReply(std::move(out));
}

// An id in a path of the view endpoint: decimal digits, at most max.
StatusOr<uint64_t> PathNumber(std::string_view text, std::string_view field, long long max) {
  uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || text.size() > 6 || error != std::errc() || end != text.data() + text.size() ||
      value > static_cast<uint64_t>(max) || !std::isdigit(static_cast<unsigned char>(text[0]))) {
    return InvalidArgument(fmt::format("{}: '{}' is not an integer from 0 to {}", field, text, max));
  }
  return value;
}

// The member view of a scene's JSON file, an array or object of it.
StatusOr<JsonValue> ViewEntry(const fs::path& root, const std::string& scene_dir, const std::string& file,
                              uint64_t view) {
  const std::string path = scene_dir + "/" + file;
  ASSIGN_OR_RETURN(const std::string bytes, ReadDatasetFile(root, path, kMaxDatasetFileBytes));
  ASSIGN_OR_RETURN(std::optional<JsonValue> entry, ParseJsonMember(bytes, std::to_string(view), path));
  if (!entry) return NotFound(fmt::format("no view {} in {}", view, path));
  return std::move(entry).value();
}

bool IsRegularFile(const fs::path& path) {
  std::error_code ec;
  return fs::symlink_status(path, ec).type() == fs::file_type::regular && !ec;
}

WebReply View(const DatasetJob& dataset, std::string_view scene_text, std::string_view view_text) {
  const auto scene = PathNumber(scene_text, "scene", kMaxSceneId);
  if (!scene.ok()) return FromStatus(scene.status());
  const auto view = PathNumber(view_text, "view", kMaxViewId);
  if (!view.ok()) return FromStatus(view.status());
  const std::string scene_id = layout::SixDigits(*scene);
  const std::string scene_dir = std::string(layout::kScenesDir) + "/" + scene_id;
  if (!IsRealDirectory(dataset.root / scene_dir)) {
    return TextReply(404, fmt::format("scene {} of dataset job {} is not complete", scene_id, dataset.job.job_id));
  }
  auto camera = ViewEntry(dataset.root, scene_dir, "scene_camera.json", *view);
  if (!camera.ok()) return FromStatus(camera.status());
  auto gt = ViewEntry(dataset.root, scene_dir, "scene_gt.json", *view);
  if (!gt.ok()) return FromStatus(gt.status());
  auto info = ViewEntry(dataset.root, scene_dir, "scene_gt_info.json", *view);
  if (!info.ok()) return FromStatus(info.status());
  if (gt->kind != JsonValue::Kind::kArray || info->kind != JsonValue::Kind::kArray ||
      gt->items.size() != info->items.size() || camera->kind != JsonValue::Kind::kObject) {
    return FromStatus(DataLoss(fmt::format("{}: scene_gt.json and scene_gt_info.json disagree on view {}", scene_dir,
                                           *view)));
  }
  const std::string image = layout::SixDigits(*view);
  const auto file = [&](const std::string& relative, bool check) {
    return !check || IsRegularFile(dataset.root / scene_dir / relative) ? JsonQuote(scene_dir + "/" + relative)
                                                                        : std::string("null");
  };
  std::string out = fmt::format("{{\"job_id\":{},\"split\":\"{}\",\"scene_id\":\"{}\",\"view\":{},\"camera\":",
                                JsonQuote(dataset.job.job_id), layout::kScenesDir, scene_id, *view);
  AppendJson(out, *camera);
  out += ",\"objects\":[";
  for (size_t i = 0; i < gt->items.size(); ++i) {
    const std::string gt_id = layout::SixDigits(i);
    out += fmt::format("{}{{\"gt_index\":{}", i ? "," : "", i);
    for (const JsonValue* entry : {&gt->items[i], &info->items[i]}) {
      for (const auto& [name, value] : entry->members) {
        out += ',' + JsonQuote(name) + ':';
        AppendJson(out, value);
      }
    }
    out += fmt::format(",\"mask_visib\":{},\"mask\":{}}}", file("mask_visib/" + image + "_" + gt_id + ".png", false),
                       file("mask/" + image + "_" + gt_id + ".png", false));
  }
  out += fmt::format("],\"images\":{{\"gray\":{},\"depth\":{},\"instances\":{},\"reasons\":{},\"cloud\":{}}}}}",
                     file("gray/" + image + ".png", true), file("depth/" + image + ".png", true),
                     file("instances/" + image + ".png", true), file("reasons/" + image + ".png", true),
                     file("cloud/" + image + ".ply", true));
  return JsonReply(std::move(out));
}

WebReply File(const DatasetJob& dataset, const std::vector<std::string_view>& segments) {
  std::string path;
  for (size_t i = 3; i < segments.size(); ++i) {
    if (i > 3) path += '/';
    path.append(segments[i]);
    if (path.size() > kMaxPathBytes) break;
  }
  auto bytes = ReadDatasetFile(dataset.root, path, kMaxDatasetFileBytes);
  if (!bytes.ok()) return FromStatus(bytes.status());
  return {200, DatasetFileType(path), std::move(bytes).value(), {}};
}

}  // namespace

StatusOr<std::vector<std::string>> CheckDatasetFilePath(std::string_view path) {
  if (path.empty()) return InvalidArgument("path", "is empty");
  if (path.size() > kMaxPathBytes) {
    return InvalidArgument("path", fmt::format("is {} or more bytes long; at most {}", path.size(), kMaxPathBytes));
  }
  if (path.front() == '/') return InvalidArgument("path", "must be relative to the dataset");
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t slash = path.find('/', start);
    parts.emplace_back(path.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start));
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  if (parts.size() > kMaxPathParts) return InvalidArgument("path", fmt::format("has more than {} parts", kMaxPathParts));
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    if (!IsWord(parts[i])) {
      return InvalidArgument("path", "folders are 1 to 64 letters, digits, '_' or '-'");
    }
  }
  const std::string& name = parts.back();
  const size_t dot = name.find('.');
  const std::string_view extension =
      dot == std::string::npos ? std::string_view() : std::string_view(name).substr(dot + 1);
  const bool known = std::any_of(std::begin(kFileTypes), std::end(kFileTypes),
                                 [&](const auto& type) { return type.first == extension; });
  if (dot == std::string::npos || !IsWord(std::string_view(name).substr(0, dot)) || !known) {
    return InvalidArgument("path", "a file name is letters, digits, '_' or '-' and .png, .json or .ply");
  }
  return parts;
}

std::string DatasetFileType(std::string_view path) {
  for (const auto& [extension, type] : kFileTypes) {
    if (path.size() > extension.size() && path.ends_with(extension) && path[path.size() - extension.size() - 1] == '.') {
      return std::string(type);
    }
  }
  return kBinaryType;
}

StatusOr<std::string> ReadDatasetFile(const fs::path& root, std::string_view path, uint64_t max_bytes) {
  ASSIGN_OR_RETURN(const std::vector<std::string> parts, CheckDatasetFilePath(path));
  Fd directory(::open(root.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  if (directory.get() < 0) return OpenFailure(path, errno);
  std::optional<Fd> inner;
  int at = directory.get();
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    inner.emplace(::openat(at, parts[i].c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
    if (inner->get() < 0) return OpenFailure(path, errno);
    at = inner->get();
  }
  // O_NONBLOCK: a FIFO put there opens without waiting for a writer (and is then refused).
  Fd file(::openat(at, parts.back().c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC));
  if (file.get() < 0) return OpenFailure(path, errno);
  struct stat status{};
  if (::fstat(file.get(), &status) != 0) return OpenFailure(path, errno);
  if (!S_ISREG(status.st_mode)) return NotFound(fmt::format("no file '{}' in the dataset", path));
  if (static_cast<uint64_t>(status.st_size) > max_bytes) {
    return ResourceExhausted(fmt::format("'{}' is {} bytes; the web view sends at most {}", path, status.st_size,
                                         max_bytes));
  }
  std::string bytes(static_cast<size_t>(status.st_size), '\0');
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(file.get(), bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Internal(fmt::format("cannot read '{}': {}", path, std::strerror(errno)));
    if (n == 0) break;
    done += static_cast<size_t>(n);
  }
  bytes.resize(done);
  return bytes;
}

WebReply ServeDatasets(const WebSources& sources, const WebApiOptions& options, const WebRequest& request) {
  (void)options;
  if (!sources.jobs || !sources.datasets) return TextReply(404, "datasets are not served");
  const auto& segments = request.segments;
  if (segments.size() == 1 || (segments.size() == 2 && segments[1].empty())) return List(sources);
  auto dataset = FindDatasetJob(sources, segments[1]);
  if (!dataset.ok()) return FromStatus(dataset.status());
  if (segments.size() == 2) return Dataset(request, *dataset);
  if (segments.size() == 6 && segments[2] == "scenes" && segments[4] == "views") {
    return View(*dataset, segments[3], segments[5]);
  }
  if (segments.size() >= 4 && segments[2] == "files") return File(*dataset, segments);
  return TextReply(404, "no such resource under /api/datasets/" + dataset->job.job_id);
}

}  // namespace vscan::web
