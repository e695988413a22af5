#include "service/datasets/format/scene_record.h"

#include <algorithm>

#include <zlib.h>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/durable_file.h"
#include "service/job/json_writer.h"

namespace vscan::service::dataset {

uint32_t Crc32(std::string_view bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  size_t at = 0;
  while (at < bytes.size()) {
    const uInt chunk = static_cast<uInt>(std::min<size_t>(bytes.size() - at, 1u << 30));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(bytes.data() + at), chunk);
    at += chunk;
  }
  return static_cast<uint32_t>(crc);
}

StatusOr<std::vector<SceneFileEntry>> ListSceneFiles(const std::filesystem::path& dir) {
  std::vector<SceneFileEntry> files;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (it->is_directory()) continue;
    const std::string relative = it->path().lexically_relative(dir).generic_string();
    if (!it->is_regular_file()) return FailedPrecondition(dir.string() + ": " + relative + " is not a regular file");
    if (relative == kSceneRecordFile) continue;
    ASSIGN_OR_RETURN(const std::string bytes, ReadWholeFile(it->path()));
    files.push_back({relative, bytes.size(), Crc32(bytes)});
  }
  if (ec) return Internal("cannot list " + dir.string() + ": " + ec.message());
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  return files;
}

std::string SceneRecordJson(const DatasetPlan& plan, const SceneKey& key, const std::vector<SceneFileEntry>& files) {
  JsonWriter json;
  json.Open('{');
  json.Key("scene_id").Value(key.scene_id);
  json.Key("seed").Value(key.seed);
  json.Key("bin").Value(plan.bins[key.bin_index]);
  json.Key("sensor").Value(plan.sensors[key.sensor_index]);
  json.Key("files").Open('[');
  for (const SceneFileEntry& file : files) {
    json.Open('{').Key("path").Value(file.path).Key("bytes").Value(file.bytes);
    json.Key("crc32").Value(uint64_t{file.crc32}).Close('}');
  }
  json.Close(']').Close('}');
  return json.str() + "\n";
}

}  // namespace vscan::service::dataset
