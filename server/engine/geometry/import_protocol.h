#pragma once
// What the vscan-mesh-import helper reads from its command line and writes to stdout.
//
// Command line: vscan-mesh-import FORMAT METRES_PER_UNIT [MEMORY_BYTES [CPU_SECONDS]], FORMAT one
// of auto, ply, obj, stl and METRES_PER_UNIT exact (hexadecimal floating point round-trips).
// Result: "VSIR", uint32 status code, uint64 payload size, then the payload: the message of an
// error, or EncodeMesh of the mesh when the code is 0. Integers are little-endian.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "geometry/mesh_import.h"

namespace vscan::geometry {

inline constexpr size_t kImportResultHeaderSize = 16;

std::string_view MeshFileFormatName(MeshFileFormat format);
std::optional<MeshFileFormat> ParseMeshFileFormat(std::string_view name);

// The header that precedes payload_size bytes of payload.
std::string ImportResultHeader(StatusCode code, uint64_t payload_size);
// What the helper writes for what its import returned: the header, then the payload (kept apart
// so that a large mesh is not copied once more to join them).
struct EncodedImportResult {
  std::string header;
  std::string payload;
};
EncodedImportResult EncodeImportResult(const StatusOr<TriangleMesh>& result);
// INTERNAL ("mesh importer: ...") unless bytes are exactly one well-formed result; otherwise the
// mesh or the status the helper sent.
StatusOr<TriangleMesh> ParseImportResult(std::string_view bytes);

}  // namespace vscan::geometry
