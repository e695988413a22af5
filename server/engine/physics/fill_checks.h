#pragma once
// FillBin's input checks: INVALID_ARGUMENT naming the offending field.

#include <vector>

#include "physics/bin_fill.h"

namespace vscan::physics {

Status CheckFillInput(const BinSpec& bin, const std::vector<PartType>& parts, const FillOptions& options);

}  // namespace vscan::physics
