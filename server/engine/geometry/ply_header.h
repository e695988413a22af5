#pragma once
// A strict check of a PLY file's header, run before the file reaches assimp: its PLY loader
// loops forever or reads out of bounds on some malformed headers.

#include <string_view>

#include "vscan/common/status.h"

namespace vscan::geometry {

// INVALID_ARGUMENT ("mesh data: ...") unless bytes open with a well-formed PLY 1.0 header whose
// element counts the rest of the file could possibly hold.
Status CheckPlyHeader(std::string_view bytes);

}  // namespace vscan::geometry
