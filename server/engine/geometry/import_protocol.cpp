#include "geometry/import_protocol.h"
#include "geometry/little_endian.h"

namespace vscan::geometry {
namespace {

constexpr std::string_view kResultMagic = "VSIR";

std::optional<StatusCode> ErrorCode(uint64_t value) {
  switch (static_cast<StatusCode>(value)) {
    case StatusCode::kCancelled:
    case StatusCode::kUnknown:
    case StatusCode::kInvalidArgument:
    case StatusCode::kDeadlineExceeded:
    case StatusCode::kNotFound:
    case StatusCode::kAlreadyExists:
    case StatusCode::kResourceExhausted:
    case StatusCode::kFailedPrecondition:
    case StatusCode::kOutOfRange:
    case StatusCode::kUnimplemented:
    case StatusCode::kInternal:
    case StatusCode::kUnavailable:
    case StatusCode::kDataLoss:
    case StatusCode::kUnauthenticated:
      return static_cast<StatusCode>(value);
    case StatusCode::kOk:
      break;
  }
  return std::nullopt;
}

}  // namespace

std::string_view MeshFileFormatName(MeshFileFormat format) {
  switch (format) {
    case MeshFileFormat::kPly:
      return "ply";
    case MeshFileFormat::kObj:
      return "obj";
    case MeshFileFormat::kStl:
      return "stl";
    case MeshFileFormat::kAuto:
      break;
  }
  return "auto";
}

std::optional<MeshFileFormat> ParseMeshFileFormat(std::string_view name) {
  for (MeshFileFormat format : {MeshFileFormat::kAuto, MeshFileFormat::kPly, MeshFileFormat::kObj,
                                MeshFileFormat::kStl}) {
    if (name == MeshFileFormatName(format)) return format;
  }
  return std::nullopt;
}

std::string ImportResultHeader(StatusCode code, uint64_t payload_size) {
  std::string out(kResultMagic);
  PutLe(out, static_cast<uint64_t>(code), 4);
  PutLe(out, payload_size, 8);
  return out;
}

EncodedImportResult EncodeImportResult(const StatusOr<TriangleMesh>& result) {
  EncodedImportResult out;
  out.payload = result.ok() ? EncodeMesh(*result) : result.status().message();
  out.header = ImportResultHeader(result.status().code(), out.payload.size());
  return out;
}

StatusOr<TriangleMesh> ParseImportResult(std::string_view bytes) {
  if (bytes.size() < kImportResultHeaderSize || !bytes.starts_with(kResultMagic)) {
    return Internal("mesh importer: no result (" + std::to_string(bytes.size()) + " bytes of output)");
  }
  const uint64_t code = GetLe(bytes.data() + 4, 4);
  const uint64_t size = GetLe(bytes.data() + 8, 8);
  std::string_view payload = bytes.substr(kImportResultHeaderSize);
  if (size != payload.size()) {
    return Internal("mesh importer: result announces " + std::to_string(size) + " bytes but carries " +
                    std::to_string(payload.size()));
  }
  if (code == 0) {
    auto mesh = DecodeMesh(payload);
    if (!mesh.ok()) return Internal("mesh importer: " + mesh.status().message());
    return mesh;
  }
  std::optional<StatusCode> error = ErrorCode(code);
  if (!error) return Internal("mesh importer: unknown status code " + std::to_string(code));
  return Status(*error, std::string(payload));
}

}  // namespace vscan::geometry
