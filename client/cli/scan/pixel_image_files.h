#pragma once
// A scan's per-pixel images as PNG files in a directory: reasons.png (8-bit PointStatus values,
// 0 where the ray met no surface) and gray.png (16-bit grey image), for `vscan scan` and
// `vscan bin scan --images DIR`.

#include <string>

#include "session/context.h"

namespace vscan::cli {

// Creates dir when missing; exit 5 when it cannot be.
int PrepareImagesDir(Context& ctx, const std::string& dir);

// Exit 5 when a file cannot be written.
int WritePixelImages(Context& ctx, const client::PixelImages& images, const std::string& dir);

}  // namespace vscan::cli
