#pragma once
// FillBin's input checks: INVALID_ARGUMENT naming the offending field.

#include <string>
#include <vector>

#include "physics/bin_fill.h"
#include "physics/part_geometry.h"

namespace vscan::physics {

Status CheckFillInput(const BinSpec& bin, const std::vector<PartType>& parts, const FillOptions& options);

// The mesh (metres) times scale: a part's own frame in the fill. INVALID_ARGUMENT naming
// "<field>.scale" when the scaled part is not 1 mm to 10 m across. Bin fills and datasets both
// scale their parts here, so a part is refused in the same words whichever plan names it.
StatusOr<TriangleMesh> ScalePart(TriangleMesh mesh, double scale, const std::string& field);

// INVALID_ARGUMENT naming "parts[i].mass_kg" for the first part whose mesh encloses no volume and
// that has no mass of its own (its density cannot give one).
Status CheckPartMasses(const std::vector<PartGeometry>& geometry);

}  // namespace vscan::physics
