#include "vscan/common/cloud_io.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <vector>

#include "cloud_columns.h"
#include "vscan/common/cloud_file_writer.h"

namespace vscan {
namespace {

static_assert(std::endian::native == std::endian::little, "binary files are read in native little-endian");

std::string ErrnoText() { return std::strerror(errno); }

// ---- PLY reading ----

struct PlyProperty {
  std::string name;
  std::string type;
  size_t size = 0;
  size_t offset = 0;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  size_t stride = 0;
  bool has_list = false;
  std::vector<PlyProperty> props;
};

size_t PlyTypeSize(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

template <typename T>
T Load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

double ReadScalar(const char* p, const std::string& t) {
  if (t == "float" || t == "float32") return Load<float>(p);
  if (t == "double" || t == "float64") return Load<double>(p);
  if (t == "uint" || t == "uint32") return Load<uint32_t>(p);
  if (t == "int" || t == "int32") return Load<int32_t>(p);
  if (t == "ushort" || t == "uint16") return Load<uint16_t>(p);
  if (t == "short" || t == "int16") return Load<int16_t>(p);
  if (t == "uchar" || t == "uint8") return Load<uint8_t>(p);
  return Load<int8_t>(p);
}

uint32_t ReadUint(const char* p, const std::string& t) {
  if (t == "uint" || t == "uint32") return Load<uint32_t>(p);
  return static_cast<uint32_t>(ReadScalar(p, t));
}

StatusOr<std::vector<PlyElement>> ParsePlyHeader(std::istream& in, const std::string& path) {
  std::string line;
  if (!std::getline(in, line) || line != "ply") return InvalidArgument(path + ": not a PLY file");
  std::vector<PlyElement> elements;
  bool format_ok = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string word;
    ss >> word;
    if (word == "end_header") {
      if (!format_ok) return InvalidArgument(path + ": only binary_little_endian PLY is supported");
      return elements;
    }
    if (word == "format") {
      std::string fmt;
      ss >> fmt;
      format_ok = fmt == "binary_little_endian";
    } else if (word == "element") {
      PlyElement e;
      ss >> e.name >> e.count;
      if (!ss) return InvalidArgument(path + ": malformed element line: " + line);
      elements.push_back(std::move(e));
    } else if (word == "property") {
      if (elements.empty()) return InvalidArgument(path + ": property before any element");
      PlyElement& e = elements.back();
      std::string type;
      ss >> type;
      if (type == "list") {
        e.has_list = true;
        continue;
      }
      PlyProperty p;
      p.type = type;
      ss >> p.name;
      p.size = PlyTypeSize(type);
      if (p.size == 0 || p.name.empty()) return InvalidArgument(path + ": unsupported property: " + line);
      p.offset = e.stride;
      e.stride += p.size;
      e.props.push_back(std::move(p));
    } else if (word != "comment" && word != "obj_info" && !word.empty()) {
      return InvalidArgument(path + ": unexpected header line: " + line);
    }
  }
  return InvalidArgument(path + ": header has no end_header");
}

const PlyProperty* FindProp(const PlyElement& e, std::initializer_list<const char*> names) {
  for (const char* n : names) {
    for (const auto& p : e.props)
      if (p.name == n) return &p;
  }
  return nullptr;
}

Status WriteWhole(const PointCloud& cloud, const std::string& path, CloudFileFormat format) {
  RETURN_IF_ERROR(cloud_file::CheckConsistent(cloud));
  ASSIGN_OR_RETURN(CloudFileWriter writer, CloudFileWriter::Open(path, format, cloud.fields, cloud.size()));
  RETURN_IF_ERROR(writer.Append(cloud));
  return writer.Finish();
}

}  // namespace

Status WritePly(const PointCloud& cloud, const std::string& path) {
  return WriteWhole(cloud, path, CloudFileFormat::kPly);
}

Status WritePcd(const PointCloud& cloud, const std::string& path) {
  return WriteWhole(cloud, path, CloudFileFormat::kPcd);
}

Status WriteCloud(const PointCloud& cloud, const std::string& path) {
  const std::optional<CloudFileFormat> format = CloudFileFormatOf(path);
  if (!format) {
    return InvalidArgument(path + ": unknown point cloud extension '" +
                           std::filesystem::path(path).extension().string() + "' (use .ply or .pcd)");
  }
  return WriteWhole(cloud, path, *format);
}

StatusOr<PointCloud> ReadPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open: " + ErrnoText());
  ASSIGN_OR_RETURN(const std::vector<PlyElement> elements, ParsePlyHeader(in, path));

  const std::streamoff body = in.tellg();
  in.seekg(0, std::ios::end);
  size_t remaining = static_cast<size_t>(in.tellg()) - static_cast<size_t>(body);
  const auto take = [&](const PlyElement& e) -> Status {
    if (e.stride != 0 && e.count > remaining / e.stride) {
      return DataLoss(path + ": truncated: element '" + e.name + "' needs " + std::to_string(e.count) + " x " +
                      std::to_string(e.stride) + " bytes");
    }
    remaining -= e.count * e.stride;
    return Status::Ok();
  };

  // Skip fixed-size elements that precede the vertices.
  size_t skip = 0;
  const PlyElement* vertex = nullptr;
  for (const auto& e : elements) {
    if (e.name == "vertex") {
      vertex = &e;
      break;
    }
    if (e.has_list) return InvalidArgument(path + ": list element '" + e.name + "' before the vertices");
    RETURN_IF_ERROR(take(e));
    skip += e.count * e.stride;
  }
  if (!vertex) return InvalidArgument(path + ": no vertex element");
  if (vertex->has_list) return InvalidArgument(path + ": vertex element has list properties");
  RETURN_IF_ERROR(take(*vertex));
  in.seekg(body + static_cast<std::streamoff>(skip));

  const PlyProperty* x = FindProp(*vertex, {"x"});
  const PlyProperty* y = FindProp(*vertex, {"y"});
  const PlyProperty* z = FindProp(*vertex, {"z"});
  if (!x || !y || !z) return InvalidArgument(path + ": vertex element needs x, y and z");
  const PlyProperty* nx = FindProp(*vertex, {"nx", "normal_x"});
  const PlyProperty* ny = FindProp(*vertex, {"ny", "normal_y"});
  const PlyProperty* nz = FindProp(*vertex, {"nz", "normal_z"});
  const PlyProperty* range = FindProp(*vertex, {"range"});
  const PlyProperty* intensity = FindProp(*vertex, {"intensity"});
  const PlyProperty* instance = FindProp(*vertex, {"instance", "instance_id"});
  const PlyProperty* pixel = FindProp(*vertex, {"pixel"});
  const PlyProperty* cx = FindProp(*vertex, {"clean_x"});
  const PlyProperty* cy = FindProp(*vertex, {"clean_y"});
  const PlyProperty* cz = FindProp(*vertex, {"clean_z"});
  const PlyProperty* incidence = FindProp(*vertex, {"incidence"});
  const PlyProperty* status = FindProp(*vertex, {"status"});
  const PlyProperty* enx = FindProp(*vertex, {"enx", "est_normal_x"});
  const PlyProperty* eny = FindProp(*vertex, {"eny", "est_normal_y"});
  const PlyProperty* enz = FindProp(*vertex, {"enz", "est_normal_z"});

  PointCloud cloud;
  cloud.fields = kFieldPosition;
  if (nx && ny && nz) cloud.fields |= kFieldNormal;
  if (range) cloud.fields |= kFieldRange;
  if (intensity) cloud.fields |= kFieldIntensity;
  if (instance) cloud.fields |= kFieldInstanceId;
  if (pixel) cloud.fields |= kFieldPixel;
  if (cx && cy && cz) cloud.fields |= kFieldCleanPosition;
  if (incidence) cloud.fields |= kFieldIncidence;
  if (status) cloud.fields |= kFieldStatus;
  if (enx && eny && enz) cloud.fields |= kFieldEstimatedNormal;
  cloud.Resize(vertex->count);

  constexpr size_t kBlockPoints = 16384;
  std::vector<char> block(std::min(vertex->count, kBlockPoints) * vertex->stride);
  for (size_t begin = 0; begin < vertex->count; begin += kBlockPoints) {
    const size_t count = std::min(kBlockPoints, vertex->count - begin);
    if (!in.read(block.data(), static_cast<std::streamsize>(count * vertex->stride))) {
      return DataLoss(path + ": read failed at vertex " + std::to_string(begin));
    }
    for (size_t k = 0; k < count; ++k) {
      const char* rec = block.data() + k * vertex->stride;
      const size_t i = begin + k;
      const auto f = [&](const PlyProperty* p) { return static_cast<float>(ReadScalar(rec + p->offset, p->type)); };
      cloud.positions[i] = {f(x), f(y), f(z)};
      if (cloud.Has(kFieldNormal)) cloud.normals[i] = {f(nx), f(ny), f(nz)};
      if (range) cloud.ranges[i] = f(range);
      if (intensity) cloud.intensities[i] = f(intensity);
      if (instance) cloud.instance_ids[i] = ReadUint(rec + instance->offset, instance->type);
      if (pixel) cloud.pixels[i] = ReadUint(rec + pixel->offset, pixel->type);
      if (cloud.Has(kFieldCleanPosition)) cloud.clean_positions[i] = {f(cx), f(cy), f(cz)};
      if (incidence) cloud.incidence_angles[i] = f(incidence);
      if (status) cloud.statuses[i] = static_cast<uint8_t>(ReadUint(rec + status->offset, status->type));
      if (cloud.Has(kFieldEstimatedNormal)) cloud.estimated_normals[i] = {f(enx), f(eny), f(enz)};
    }
  }
  return cloud;
}

}  // namespace vscan
