// ReadPcd and ParsePcd: the header of a binary PCD v0.7; the point records are decoded in
// cloud_records.

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "cloud_records.h"
#include "memory_stream.h"
#include "vscan/common/cloud_io.h"

namespace vscan {
namespace {

using cloud_records::RecordLayout;
using cloud_records::ScalarType;

// Far above any real PCD field (FPFH has 33 values, VFH 308); also refuses "-1", which an
// unsigned stream read takes as SIZE_MAX, so that record strides cannot wrap around.
constexpr size_t kMaxPcdCount = 1 << 16;

struct PcdField {
  std::string name;
  size_t size = 4;
  char type = 'F';
  size_t count = 1;
};

struct PcdHeader {
  RecordLayout layout;
  size_t points = 0;
};

std::optional<ScalarType> PcdScalarType(char type, size_t size) {
  switch (type) {
    case 'F':
      if (size == 4) return ScalarType::kFloat32;
      if (size == 8) return ScalarType::kFloat64;
      return std::nullopt;
    case 'U':
      if (size == 1) return ScalarType::kUint8;
      if (size == 2) return ScalarType::kUint16;
      if (size == 4) return ScalarType::kUint32;
      if (size == 8) return ScalarType::kUint64;
      return std::nullopt;
    case 'I':
      if (size == 1) return ScalarType::kInt8;
      if (size == 2) return ScalarType::kInt16;
      if (size == 4) return ScalarType::kInt32;
      if (size == 8) return ScalarType::kInt64;
      return std::nullopt;
    default: return std::nullopt;
  }
}

template <typename T>
Status ReadList(std::istringstream& ss, std::vector<PcdField>& fields, T PcdField::*member, const std::string& path,
                const char* key) {
  for (PcdField& f : fields) {
    if (!(ss >> f.*member)) return InvalidArgument(path + ": PCD " + key + " line has too few entries");
  }
  return Status::Ok();
}

StatusOr<PcdHeader> ParseHeader(std::istream& in, const std::string& path) {
  PcdHeader h;
  std::vector<PcdField> fields;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "FIELDS") {
      for (std::string name; ss >> name;) fields.push_back({name});
    } else if (key == "SIZE") {
      RETURN_IF_ERROR(ReadList(ss, fields, &PcdField::size, path, "SIZE"));
    } else if (key == "TYPE") {
      RETURN_IF_ERROR(ReadList(ss, fields, &PcdField::type, path, "TYPE"));
    } else if (key == "COUNT") {
      RETURN_IF_ERROR(ReadList(ss, fields, &PcdField::count, path, "COUNT"));
    } else if (key == "POINTS") {
      if (!(ss >> h.points)) return InvalidArgument(path + ": malformed POINTS line: " + line);
    } else if (key == "DATA") {
      std::string kind;
      ss >> kind;
      if (kind != "binary") return InvalidArgument(path + ": only binary PCD data is supported, not '" + kind + "'");
      for (const PcdField& f : fields) {
        const std::optional<ScalarType> type = PcdScalarType(f.type, f.size);
        if (!type || f.count == 0 || f.count > kMaxPcdCount) {
          return InvalidArgument(path + ": PCD field '" + f.name + "' has an unsupported SIZE/TYPE/COUNT");
        }
        h.layout.Add(f.name, *type, f.count);
      }
      return h;
    }
  }
  return InvalidArgument(path + ": PCD header has no DATA line");
}

StatusOr<PointCloud> ReadPcdStream(std::istream& in, const std::string& path, uint64_t max_bytes) {
  ASSIGN_OR_RETURN(const PcdHeader h, ParseHeader(in, path));

  const std::streamoff body = in.tellg();
  in.seekg(0, std::ios::end);
  const size_t available = static_cast<size_t>(in.tellg() - body);
  const size_t stride = h.layout.stride;
  if (stride != 0 && h.points > available / stride) {
    return DataLoss(path + ": truncated: " + std::to_string(h.points) + " points need " +
                    std::to_string(h.points * stride) + " bytes, the file has " + std::to_string(available));
  }
  in.seekg(body);
  return cloud_records::ReadRecords(in, h.layout, h.points, path, max_bytes);
}

}  // namespace

StatusOr<PointCloud> ReadPcd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open: " + std::strerror(errno));
  return ReadPcdStream(in, path, std::numeric_limits<uint64_t>::max());
}

StatusOr<PointCloud> ParsePcd(std::string_view bytes, const std::string& where, uint64_t max_bytes) {
  cloud_records::MemoryStream in(bytes);
  return ReadPcdStream(in, where, max_bytes);
}

}  // namespace vscan
