#pragma once
// How far the parts' own triangle meshes overlap at their settled poses, one another and the bin:
// not the collision shapes the solver saw, but the meshes a scan sees.

#include <vector>

#include "physics/bin_fill.h"

namespace vscan::physics {

// The depth is found to within this (metres): along an edge the depth changes by at most the
// distance moved, and each edge is bisected until no piece can hold a point this much deeper.
inline constexpr double kMeshOverlapResolution = 0.00002;

// For each pair of parts: the deepest vertex or edge point of either mesh inside the other (the
// distance to that mesh's surface; the meshes must be closed). For each part and the bin: a box
// bin's slabs are solid boxes, tested both ways; a mesh bin is a shell: the part's points behind
// the nearest bin triangle (seen from the part's centre) and the bin's vertices and edges inside
// the part. `placed` indexes `parts` by type.
MeshOverlaps MeasureMeshOverlaps(const BinSpec& bin, const std::vector<PartType>& parts,
                                 const std::vector<PlacedPart>& placed);

// After a fill: while some pair of parts (or a part and a box bin) overlaps by more than `bound`,
// moves the parts apart, at most `rounds` times. A round takes the overlaps past the bound deepest
// first and pushes each apart at once (its parts' overlaps measured again before the next): a pair
// its depth plus a quarter of the bound, half each, from the deepest point to the nearest surface,
// where a box bin's floor or wall stops one part's half the other part taking it; a part in a box
// bin's slab all of it, out through the slab's nearest face. Translations only. Returns the
// overlaps measured after the last move (bound not met when rounds ran out).
MeshOverlaps SeparateMeshOverlaps(const BinSpec& bin, const std::vector<PartType>& parts,
                                  std::vector<PlacedPart>& placed, double bound, int rounds);

}  // namespace vscan::physics
