#pragma once
// A robot bundle (its files by path) as one stored blob, in a small versioned format:
// "VSRB", u32 version (1), u32 file count, then per file a u64-length-prefixed path and content,
// all little-endian, files in path order so that equal bundles give equal blobs.

#include <string>
#include <string_view>
#include <vector>

#include "robot/bundle_paths.h"
#include "robot/urdf_bundle.h"
#include "vscan/common/status.h"

namespace vscan::robot_registry {

std::string EncodeBundle(const robot::BundleFiles& files);

// DATA_LOSS for anything but a well-formed version 1 blob.
StatusOr<std::vector<robot::BundleFile>> DecodeBundle(std::string_view blob);

}  // namespace vscan::robot_registry
