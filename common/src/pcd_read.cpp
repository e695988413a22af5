// ReadPcd and ParsePcd: the header of a PCD v0.7 with binary, ascii or binary_compressed (LZF)
// data; the point records are decoded in cloud_records.

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include "ascii_records.h"
#include "cloud_records.h"
#include "lzf_decode.h"
#include "memory_stream.h"
#include "vscan/common/cloud_io.h"
#include "vscan/common/text_excerpt.h"

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

enum class PcdData { kBinary, kAscii, kCompressed };

struct PcdHeader {
  RecordLayout layout;
  size_t points = 0;
  PcdData data = PcdData::kBinary;
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
      if (!(ss >> h.points)) return InvalidArgument(path + ": malformed POINTS line: " + TextExcerpt(line));
    } else if (key == "DATA") {
      std::string kind;
      ss >> kind;
      if (kind == "binary") {
        h.data = PcdData::kBinary;
      } else if (kind == "ascii") {
        h.data = PcdData::kAscii;
      } else if (kind == "binary_compressed") {
        h.data = PcdData::kCompressed;
      } else {
        return InvalidArgument(path + ": DATA: '" + kind + "' is none of binary, ascii and binary_compressed");
      }
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

StatusOr<PointCloud> ReadAsciiPoints(std::string_view text, const PcdHeader& h, const std::string& path,
                                     uint64_t max_bytes) {
  cloud_records::AsciiRecords records(text, h.layout, path, "point");
  RETURN_IF_ERROR(records.CheckRoom(h.points));
  return cloud_records::DecodeRecords(h.layout, h.points, path, max_bytes, [&](char* out, size_t first, size_t n) {
    return records.Fill(out, first, n);
  });
}

template <typename T>
T LoadLe(std::string_view bytes) {
  T v;
  std::memcpy(&v, bytes.data(), sizeof(T));
  return v;
}

// binary_compressed: two uint32 sizes, then LZF data that decompresses to the points field by field
// (every point's first field, then every point's second...). Both sizes are checked against the
// header and the file before anything is allocated or decompressed.
StatusOr<PointCloud> ReadCompressedPoints(std::string_view body, const PcdHeader& h, const std::string& path,
                                          uint64_t max_bytes) {
  if (body.size() < 8) return DataLoss(path + ": truncated: binary_compressed data has no sizes");
  const uint32_t compressed = LoadLe<uint32_t>(body);
  const uint32_t uncompressed = LoadLe<uint32_t>(body.substr(4));
  body.remove_prefix(8);
  const size_t stride = h.layout.stride;
  if (compressed > body.size()) {
    return DataLoss(path + ": truncated: binary_compressed data declares " + std::to_string(compressed) +
                    " compressed bytes, the file has " + std::to_string(body.size()));
  }
  if (stride == 0 || h.points != uncompressed / stride || uncompressed % stride != 0) {
    return InvalidArgument(path + ": binary_compressed data declares " + std::to_string(uncompressed) +
                           " uncompressed bytes, POINTS " + std::to_string(h.points) + " of " +
                           std::to_string(stride) + " bytes need " + std::to_string(h.points * stride));
  }
  if (uncompressed > uint64_t{compressed} * cloud_records::kLzfMaxRatio) {
    return InvalidArgument(path + ": binary_compressed data declares " + std::to_string(uncompressed) +
                           " uncompressed bytes from " + std::to_string(compressed) +
                           ", more than LZF can expand to");
  }
  if (uncompressed > max_bytes) {
    return ResourceExhausted(path + ": binary_compressed data of " + std::to_string(uncompressed) +
                             " bytes takes more than the limit of " + std::to_string(max_bytes) + " bytes");
  }
  std::vector<char> fields;
  return cloud_records::DecodeRecords(h.layout, h.points, path, max_bytes, [&](char* out, size_t first, size_t n) {
    if (fields.empty() && uncompressed != 0) {
      fields.resize(uncompressed);
      if (!cloud_records::LzfDecompress(body.substr(0, compressed), fields.data(), fields.size())) {
        return DataLoss(path + ": binary_compressed data is not a valid LZF stream of " +
                        std::to_string(uncompressed) + " bytes");
      }
    }
    for (const cloud_records::RecordProperty& p : h.layout.properties) {
      const size_t bytes = cloud_records::ScalarSize(p.type) * p.count;
      const char* column = fields.data() + h.points * p.offset + first * bytes;
      char* to = out + p.offset;
      if (bytes == 4) {  // the common case, a fixed-size copy the compiler inlines
        for (size_t k = 0; k < n; ++k) std::memcpy(to + k * stride, column + k * 4, 4);
      } else {
        for (size_t k = 0; k < n; ++k) std::memcpy(to + k * stride, column + k * bytes, bytes);
      }
    }
    return Status::Ok();
  });
}

// `whole`, when set, is the stream's bytes (an upload), read in place rather than copied.
StatusOr<PointCloud> ReadPcdStream(std::istream& in, std::optional<std::string_view> whole, const std::string& path,
                                   uint64_t max_bytes) {
  ASSIGN_OR_RETURN(const PcdHeader h, ParseHeader(in, path));

  const std::streamoff body = in.tellg();
  // The header's last line ran to the end of the bytes: nothing follows it.
  if (body < 0) return DataLoss(path + ": truncated: the header's last line has no end of line and no data follows");
  if (h.data != PcdData::kBinary) {
    std::string copy;
    std::string_view rest;
    if (whole) {
      rest = whole->substr(static_cast<size_t>(body));
    } else {
      copy.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      rest = copy;
    }
    return h.data == PcdData::kAscii ? ReadAsciiPoints(rest, h, path, max_bytes)
                                     : ReadCompressedPoints(rest, h, path, max_bytes);
  }
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
  return ReadPcdStream(in, std::nullopt, path, std::numeric_limits<uint64_t>::max());
}

StatusOr<PointCloud> ParsePcd(std::string_view bytes, const std::string& where, uint64_t max_bytes) {
  cloud_records::MemoryStream in(bytes);
  return ReadPcdStream(in, bytes, where, max_bytes);
}

}  // namespace vscan
