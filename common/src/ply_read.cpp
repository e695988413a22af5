// ReadPly and ParsePly: the header of a binary little-endian or ASCII PLY; the vertex records are
// decoded in cloud_records (ASCII ones through ascii_records).

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
#include "memory_stream.h"
#include "vscan/common/cloud_io.h"
#include "vscan/common/text_excerpt.h"

namespace vscan {
namespace {

using cloud_records::RecordLayout;
using cloud_records::ScalarType;

struct PlyElement {
  std::string name;
  size_t count = 0;
  bool has_list = false;
  RecordLayout layout;
};

std::optional<ScalarType> PlyScalarType(const std::string& t) {
  if (t == "char" || t == "int8") return ScalarType::kInt8;
  if (t == "uchar" || t == "uint8") return ScalarType::kUint8;
  if (t == "short" || t == "int16") return ScalarType::kInt16;
  if (t == "ushort" || t == "uint16") return ScalarType::kUint16;
  if (t == "int" || t == "int32") return ScalarType::kInt32;
  if (t == "uint" || t == "uint32") return ScalarType::kUint32;
  if (t == "float" || t == "float32") return ScalarType::kFloat32;
  if (t == "double" || t == "float64") return ScalarType::kFloat64;
  return std::nullopt;
}

struct PlyHeader {
  std::vector<PlyElement> elements;
  bool ascii = false;
};

StatusOr<PlyHeader> ParsePlyHeader(std::istream& in, const std::string& path) {
  std::string line;
  if (!std::getline(in, line) || (line != "ply" && line != "ply\r")) return InvalidArgument(path + ": not a PLY file");
  PlyHeader header;
  std::vector<PlyElement>& elements = header.elements;
  bool format_ok = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string word;
    ss >> word;
    if (word == "end_header") {
      if (!format_ok) return InvalidArgument(path + ": format: only binary_little_endian and ascii PLY are supported");
      return header;
    }
    if (word == "format") {
      std::string fmt;
      ss >> fmt;
      format_ok = fmt == "binary_little_endian" || fmt == "ascii";
      header.ascii = fmt == "ascii";
    } else if (word == "element") {
      PlyElement e;
      ss >> e.name >> e.count;
      if (!ss) return InvalidArgument(path + ": malformed element line: " + TextExcerpt(line));
      elements.push_back(std::move(e));
    } else if (word == "property") {
      if (elements.empty()) return InvalidArgument(path + ": property before any element");
      PlyElement& e = elements.back();
      std::string type, name;
      ss >> type;
      if (type == "list") {
        e.has_list = true;
        continue;
      }
      ss >> name;
      const std::optional<ScalarType> scalar = PlyScalarType(type);
      if (!scalar || name.empty()) return InvalidArgument(path + ": unsupported property: " + TextExcerpt(line));
      e.layout.Add(std::move(name), *scalar);
    } else if (word != "comment" && word != "obj_info" && !word.empty()) {
      return InvalidArgument(path + ": unexpected header line: " + TextExcerpt(line));
    }
  }
  return InvalidArgument(path + ": header has no end_header");
}

// The vertex element; `before` sees each fixed-size element that precedes it. Elements of lists
// before the vertices, list properties in them, or no vertex element at all are refused.
template <typename Before>
StatusOr<const PlyElement*> FindVertices(const std::vector<PlyElement>& elements, const std::string& path,
                                         Before before) {
  for (const auto& e : elements) {
    if (e.name == "vertex") {
      if (e.has_list) return InvalidArgument(path + ": vertex element has list properties");
      return &e;
    }
    if (e.has_list) return InvalidArgument(path + ": list element '" + e.name + "' before the vertices");
    RETURN_IF_ERROR(before(e));
  }
  return InvalidArgument(path + ": no vertex element");
}

// The vertices of an ASCII body: the records before them are stepped over value by value.
StatusOr<PointCloud> ReadAsciiVertices(std::string_view body, const std::vector<PlyElement>& elements,
                                       const std::string& path, uint64_t max_bytes) {
  size_t skip = 0;
  ASSIGN_OR_RETURN(const PlyElement* vertex, FindVertices(elements, path, [&](const PlyElement& e) -> Status {
    const size_t values = e.layout.properties.size();
    if (values != 0 && e.count > (std::numeric_limits<size_t>::max() - skip) / values) {
      return InvalidArgument(path + ": element '" + e.name + "': count " + std::to_string(e.count) + " is too large");
    }
    skip += e.count * values;
    return Status::Ok();
  }));
  cloud_records::AsciiRecords records(body, vertex->layout, path, "vertex");
  RETURN_IF_ERROR(records.CheckRoom(vertex->count, skip));
  RETURN_IF_ERROR(records.Skip(skip));
  return cloud_records::DecodeRecords(vertex->layout, vertex->count, path, max_bytes,
                                      [&](char* out, size_t first, size_t points) {
                                        return records.Fill(out, first, points);
                                      });
}

// `whole`, when set, is the stream's bytes (an upload), read in place rather than copied.
StatusOr<PointCloud> ReadPlyStream(std::istream& in, std::optional<std::string_view> whole, const std::string& path,
                                   uint64_t max_bytes) {
  ASSIGN_OR_RETURN(const PlyHeader header, ParsePlyHeader(in, path));
  const std::vector<PlyElement>& elements = header.elements;

  const std::streamoff body = in.tellg();
  // The header's last line ran to the end of the bytes: nothing follows it.
  if (body < 0) return DataLoss(path + ": truncated: the header's last line has no end of line and no data follows");
  if (header.ascii) {
    if (whole) return ReadAsciiVertices(whole->substr(static_cast<size_t>(body)), elements, path, max_bytes);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    return ReadAsciiVertices(text, elements, path, max_bytes);
  }
  in.seekg(0, std::ios::end);
  size_t remaining = static_cast<size_t>(in.tellg()) - static_cast<size_t>(body);
  const auto take = [&](const PlyElement& e) -> Status {
    const size_t stride = e.layout.stride;
    if (stride != 0 && e.count > remaining / stride) {
      return DataLoss(path + ": truncated: element '" + e.name + "' needs " + std::to_string(e.count) + " x " +
                      std::to_string(stride) + " bytes");
    }
    remaining -= e.count * stride;
    return Status::Ok();
  };

  // Skip fixed-size elements that precede the vertices.
  size_t skip = 0;
  ASSIGN_OR_RETURN(const PlyElement* vertex, FindVertices(elements, path, [&](const PlyElement& e) -> Status {
    RETURN_IF_ERROR(take(e));
    skip += e.count * e.layout.stride;
    return Status::Ok();
  }));
  RETURN_IF_ERROR(take(*vertex));
  in.seekg(body + static_cast<std::streamoff>(skip));
  return cloud_records::ReadRecords(in, vertex->layout, vertex->count, path, max_bytes);
}

}  // namespace

StatusOr<PointCloud> ReadPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open: " + std::strerror(errno));
  return ReadPlyStream(in, std::nullopt, path, std::numeric_limits<uint64_t>::max());
}

StatusOr<PointCloud> ParsePly(std::string_view bytes, const std::string& where, uint64_t max_bytes) {
  cloud_records::MemoryStream in(bytes);
  return ReadPlyStream(in, bytes, where, max_bytes);
}

}  // namespace vscan
