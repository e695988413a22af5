#pragma once
// The marching-cubes case table, generated at start-up from the cube's geometry rather than typed
// in: for each of the 256 inside/outside patterns of a cube's corners, triangles over its edges.
//
// Corner c sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1). Edge 4 * a + k runs along axis a
// from EdgeStart(e) to EdgeStart(e) + unit(a). A corner is inside when its bit in the case is set
// (negative distance); triangles wind counter-clockwise seen from outside.

#include <array>
#include <cstdint>
#include <vector>

namespace vscan::reconstruction {

using CubeTriangle = std::array<uint8_t, 3>;  // edge ids

// The triangles of case `inside_mask`.
const std::vector<CubeTriangle>& CubeCase(uint32_t inside_mask);

// Corner at which edge e starts, and the axis it runs along.
int EdgeStart(int edge);
inline int EdgeAxis(int edge) { return edge / 4; }

}  // namespace vscan::reconstruction
