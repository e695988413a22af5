#pragma once
// Files that survive a crash once written: data and directory entries are flushed to the disk
// before the caller goes on, so a rename that publishes them never points at missing bytes.

#include <filesystem>
#include <string>
#include <string_view>

#include "vscan/common/status.h"

namespace vscan::service::dataset {

// Creates or replaces path with bytes and flushes it.
Status WriteFileDurably(const std::filesystem::path& path, std::string_view bytes);
// Flushes the directory's entries (after a create, rename or remove inside it).
Status SyncDirectory(const std::filesystem::path& dir);
// Replaces `to` by `from` in one step and flushes the directory holding `to`.
Status RenameDurably(const std::filesystem::path& from, const std::filesystem::path& to);
// Writes bytes to path + temp_suffix, flushes them, then renames that over path: a crash leaves the
// old file or the new one, never half of it. Writers that may race pass suffixes of their own.
Status ReplaceFileDurably(const std::filesystem::path& path, std::string_view bytes, std::string_view temp_suffix);
StatusOr<std::string> ReadWholeFile(const std::filesystem::path& path);

}  // namespace vscan::service::dataset
