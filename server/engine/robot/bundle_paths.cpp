#include "robot/bundle_paths.h"

#include <algorithm>
#include <vector>

namespace vscan::robot {
namespace {

constexpr std::string_view kPackageScheme = "package://";

std::string Quoted(std::string_view s) {
  std::string out(1, '\'');
  out.append(s).push_back('\'');
  return out;
}

std::vector<std::string_view> SplitComponents(std::string_view path) {
  std::vector<std::string_view> parts;
  size_t start = 0;
  while (start <= path.size()) {
    const size_t end = std::min(path.find('/', start), path.size());
    parts.push_back(path.substr(start, end - start));
    start = end + 1;
  }
  return parts;
}

std::string Join(const std::vector<std::string_view>& parts, size_t first) {
  std::string out;
  for (size_t i = first; i < parts.size(); ++i) {
    if (i > first) out += '/';
    out += parts[i];
  }
  return out;
}

// Sets *escapes when the path climbs above the bundle root, so callers need not read the message.
StatusOr<std::string> Normalize(std::string_view path, std::string_view field, bool* escapes) {
  const std::string f(field);
  if (path.empty()) return InvalidArgument(f, "empty path");
  if (path.find('\0') != std::string_view::npos) return InvalidArgument(f, "path contains a NUL byte");
  if (path.find('\\') != std::string_view::npos) {
    return InvalidArgument(f, Quoted(path) + " contains a backslash; use '/' separators");
  }
  if (path.front() == '/') return InvalidArgument(f, Quoted(path) + " is absolute; paths are relative to the bundle root");
  std::vector<std::string_view> kept;
  for (std::string_view part : SplitComponents(path)) {
    if (part.empty() || part == ".") continue;
    if (part == "..") {
      if (kept.empty()) {
        *escapes = true;
        return InvalidArgument(f, Quoted(path) + " escapes the bundle root");
      }
      kept.pop_back();
      continue;
    }
    kept.push_back(part);
  }
  if (kept.empty()) return InvalidArgument(f, Quoted(path) + " names the bundle root, not a file");
  return Join(kept, 0);
}

// Normalises a mesh path; an escape names the filename as the user wrote it.
StatusOr<std::string> NormalizeMeshPath(std::string_view path, std::string_view filename,
                                        std::string_view field) {
  bool escapes = false;
  StatusOr<std::string> normalized = Normalize(path, field, &escapes);
  if (normalized.ok()) return normalized;
  return InvalidArgument(std::string(field), "mesh " + Quoted(filename) +
                                                 (escapes ? " escapes the bundle" : " is not a valid bundle path"));
}

}  // namespace

StatusOr<std::string> NormalizeBundlePath(std::string_view path, std::string_view field) {
  bool escapes = false;
  return Normalize(path, field, &escapes);
}

std::string ParentDirectory(std::string_view normalized_path) {
  const size_t slash = normalized_path.rfind('/');
  return slash == std::string_view::npos ? std::string() : std::string(normalized_path.substr(0, slash));
}

StatusOr<MeshLocation> ResolveMeshReference(std::string_view filename, std::string_view urdf_dir,
                                            const BundleFiles& files, std::string_view field) {
  const std::string f(field);
  if (filename.empty()) return InvalidArgument(f, "empty mesh filename");
  MeshLocation location;
  if (filename.substr(0, kPackageScheme.size()) == kPackageScheme) {
    ASSIGN_OR_RETURN(std::string full, NormalizeMeshPath(filename.substr(kPackageScheme.size()), filename, field));
    const std::vector<std::string_view> parts = SplitComponents(full);
    for (size_t first = 0; first < parts.size(); ++first) {
      std::string candidate = Join(parts, first);
      if (files.count(candidate) > 0) return MeshLocation{std::move(candidate), true};
    }
    location.bundle_path = std::move(full);
    return location;
  }
  if (filename.substr(0, 7) == "file://") {
    return InvalidArgument(f, "mesh " + Quoted(filename) +
                           " is a file:// URI; bundle meshes must be relative paths or package:// URIs");
  }
  if (filename.find("://") != std::string_view::npos) {
    return InvalidArgument(f, "mesh " + Quoted(filename) + " has an unsupported URI scheme");
  }
  if (filename.front() == '/') {
    return InvalidArgument(f, "mesh " + Quoted(filename) + " is an absolute path and escapes the bundle");
  }
  const std::string joined = urdf_dir.empty() ? std::string(filename) : std::string(urdf_dir) + "/" + std::string(filename);
  ASSIGN_OR_RETURN(location.bundle_path, NormalizeMeshPath(joined, filename, field));
  location.found = files.count(location.bundle_path) > 0;
  return location;
}

}  // namespace vscan::robot
