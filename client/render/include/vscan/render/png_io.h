#pragma once
// 8-bit RGB PNG files through libpng.

#include <string>

#include "vscan/common/status.h"
#include "vscan/render/image.h"

namespace vscan::render {

// Writes to a temporary file beside path, then renames it into place.
Status WritePng(const Image& image, const std::string& path);
// Reads any 8-bit or 16-bit PNG as RGB (alpha dropped, grey expanded, palettes resolved).
StatusOr<Image> ReadPng(const std::string& path);

}  // namespace vscan::render
