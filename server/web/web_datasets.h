#pragma once
// /api/datasets: the dataset jobs and what their directories hold (docs/DATASETS.md, "Layout"),
// read as they are written: a scene is listed once its directory has its final name, which the
// writer gives it only when every file of it is complete and flushed (scene_writer.h).

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "vscan/common/status.h"
#include "web/web_request.h"
#include "web/web_sources.h"

namespace vscan::web {

struct WebApiOptions;

// segments[0] is "datasets".
WebReply ServeDatasets(const WebSources& sources, const WebApiOptions& options, const WebRequest& request);

// Files /api/datasets/{id}/files/ sends, and scene JSON files a view is read from, are at most this
// large; larger ones are refused (422).
inline constexpr uint64_t kMaxDatasetFileBytes = uint64_t{64} << 20;

// A path inside a dataset as the API takes it: at most 256 bytes in 1 to 8 parts between single
// '/', no leading '/'; folders of letters, digits, '_' and '-'; a file name of those with one '.'
// before png, json or ply. So no "..", ".", "%2e", hidden names, "*.partial" scenes or temporary
// files. Returns the parts; INVALID_ARGUMENT naming "path" otherwise.
StatusOr<std::vector<std::string>> CheckDatasetFilePath(std::string_view path);

// The content type of a path CheckDatasetFilePath accepted: image/png, application/json,
// application/octet-stream (ply).
std::string DatasetFileType(std::string_view path);

// The bytes of root/path, a path CheckDatasetFilePath accepts, opened a part at a time without
// following a symbolic link (root itself included): INVALID_ARGUMENT for a path it refuses, NOT_FOUND
// when a part is missing, a link or not a regular file, RESOURCE_EXHAUSTED past max_bytes.
StatusOr<std::string> ReadDatasetFile(const std::filesystem::path& root, std::string_view path, uint64_t max_bytes);

}  // namespace vscan::web
