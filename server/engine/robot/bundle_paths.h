#pragma once
// Paths inside an uploaded robot bundle: normalisation and mesh-reference resolution.

#include <map>
#include <string>
#include <string_view>

#include "vscan/common/status.h"

namespace vscan::robot {

// Bundle contents keyed by normalised path.
using BundleFiles = std::map<std::string, std::string, std::less<>>;

// Normalises a bundle-relative path: '/' separators, "." and empty components dropped, ".."
// folding the component before it. Refuses absolute paths, backslashes, NUL bytes, a ".." that
// climbs above the bundle root and paths naming the root itself; messages start with field.
StatusOr<std::string> NormalizeBundlePath(std::string_view path, std::string_view field);

// Directory part of a normalised path: "a/b/c.stl" -> "a/b", "c.stl" -> "".
std::string ParentDirectory(std::string_view normalized_path);

// Where a mesh reference points inside the bundle. found is false when the reference is well
// formed but no bundle file matches (a warning, not an error).
struct MeshLocation {
  std::string bundle_path;  // normalised; for an unmatched package:// reference, "<pkg>/<rest>"
  bool found = false;
};

// Resolves a URDF mesh filename against the bundle:
// - "package://<pkg>/<rest>": "<pkg>/<rest>" is normalised; the bundle file whose path is the
//   longest whole-component suffix of it wins, so "package://p/robots/d/meshes/a.stl" finds
//   "p/robots/d/meshes/a.stl", else "robots/d/meshes/a.stl", ..., else "meshes/a.stl", else "a.stl".
// - a relative path: relative to urdf_dir (the URDF's directory inside the bundle).
// - "file://", absolute paths, other URI schemes and anything escaping the bundle root after
//   normalisation: InvalidArgument naming field and the filename.
StatusOr<MeshLocation> ResolveMeshReference(std::string_view filename, std::string_view urdf_dir,
                                            const BundleFiles& files, std::string_view field);

}  // namespace vscan::robot
