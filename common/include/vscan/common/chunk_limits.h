#pragma once
// The size of one streamed scan chunk: the server enforces it, clients check it before asking.

#include <cstddef>

namespace vscan {

inline constexpr size_t kDefaultChunkBytes = size_t{1} << 20;
// A request that leaves chunk_bytes unset gets at most this many points a chunk as well: with few
// bytes a point, a whole MiB is a tenth of a frame, and the first chunk waits for it.
inline constexpr size_t kDefaultChunkPoints = 32768;
inline constexpr size_t kMinChunkBytes = size_t{16} << 10;
inline constexpr size_t kMaxChunkBytes = size_t{3} << 20;  // stays under gRPC's default 4 MiB receive limit

}  // namespace vscan
