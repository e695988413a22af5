#include "pcd_read.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace vscan::render {
namespace {

struct PcdField {
  std::string name;
  size_t size = 4;
  char type = 'F';
  size_t count = 1;
  size_t offset = 0;
};

struct PcdHeader {
  std::vector<PcdField> fields;
  size_t points = 0;
  size_t stride = 0;
};

template <typename T>
T Load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

double ReadScalar(const char* p, const PcdField& f) {
  if (f.type == 'F') return f.size == 8 ? Load<double>(p) : Load<float>(p);
  if (f.type == 'U') {
    switch (f.size) {
      case 1: return Load<uint8_t>(p);
      case 2: return Load<uint16_t>(p);
      case 8: return static_cast<double>(Load<uint64_t>(p));
      default: return Load<uint32_t>(p);
    }
  }
  switch (f.size) {
    case 1: return Load<int8_t>(p);
    case 2: return Load<int16_t>(p);
    case 8: return static_cast<double>(Load<int64_t>(p));
    default: return Load<int32_t>(p);
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
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "FIELDS") {
      for (std::string name; ss >> name;) h.fields.push_back({name});
    } else if (key == "SIZE") {
      RETURN_IF_ERROR(ReadList(ss, h.fields, &PcdField::size, path, "SIZE"));
    } else if (key == "TYPE") {
      RETURN_IF_ERROR(ReadList(ss, h.fields, &PcdField::type, path, "TYPE"));
    } else if (key == "COUNT") {
      RETURN_IF_ERROR(ReadList(ss, h.fields, &PcdField::count, path, "COUNT"));
    } else if (key == "POINTS") {
      ss >> h.points;
    } else if (key == "DATA") {
      std::string kind;
      ss >> kind;
      if (kind != "binary") return InvalidArgument(path + ": only binary PCD data is supported, not '" + kind + "'");
      for (PcdField& f : h.fields) {
        const bool size_ok = f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8;
        if (!size_ok || (f.type != 'F' && f.type != 'U' && f.type != 'I') || (f.type == 'F' && f.size < 4)) {
          return InvalidArgument(path + ": PCD field '" + f.name + "' has an unsupported SIZE/TYPE");
        }
        f.offset = h.stride;
        h.stride += f.size * f.count;
      }
      return h;
    }
  }
  return InvalidArgument(path + ": PCD header has no DATA line");
}

const PcdField* Find(const PcdHeader& h, const char* name) {
  for (const PcdField& f : h.fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

// The three fields of a vector column; present only when all three are.
struct Vec3Fields {
  const PcdField* x = nullptr;
  const PcdField* y = nullptr;
  const PcdField* z = nullptr;
  explicit operator bool() const { return x && y && z; }
};

Vec3Fields FindVec3(const PcdHeader& h, const char* x, const char* y, const char* z) {
  return {Find(h, x), Find(h, y), Find(h, z)};
}

}  // namespace

StatusOr<PointCloud> ReadPcd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open: " + std::strerror(errno));
  ASSIGN_OR_RETURN(const PcdHeader h, ParseHeader(in, path));
  const PcdField* x = Find(h, "x");
  const PcdField* y = Find(h, "y");
  const PcdField* z = Find(h, "z");
  if (!x || !y || !z) return InvalidArgument(path + ": PCD needs x, y and z fields");
  const Vec3Fields normal = FindVec3(h, "normal_x", "normal_y", "normal_z");
  const Vec3Fields clean = FindVec3(h, "clean_x", "clean_y", "clean_z");
  const Vec3Fields estimated = FindVec3(h, "est_normal_x", "est_normal_y", "est_normal_z");
  const PcdField* range = Find(h, "range");
  const PcdField* intensity = Find(h, "intensity");
  const PcdField* instance = Find(h, "instance");
  const PcdField* pixel = Find(h, "pixel");
  const PcdField* incidence = Find(h, "incidence");
  const PcdField* status = Find(h, "status");

  const std::streamoff body = in.tellg();
  in.seekg(0, std::ios::end);
  const size_t available = static_cast<size_t>(in.tellg() - body);
  if (h.stride == 0 || h.points > available / h.stride) {
    return DataLoss(path + ": truncated: " + std::to_string(h.points) + " points need " +
                    std::to_string(h.points * h.stride) + " bytes, the file has " + std::to_string(available));
  }
  in.seekg(body);
  std::vector<char> data(h.points * h.stride);
  if (!in.read(data.data(), static_cast<std::streamsize>(data.size()))) return DataLoss(path + ": read failed");

  PointCloud cloud;
  cloud.fields = kFieldPosition;
  if (normal) cloud.fields |= kFieldNormal;
  if (range) cloud.fields |= kFieldRange;
  if (intensity) cloud.fields |= kFieldIntensity;
  if (instance) cloud.fields |= kFieldInstanceId;
  if (pixel) cloud.fields |= kFieldPixel;
  if (clean) cloud.fields |= kFieldCleanPosition;
  if (incidence) cloud.fields |= kFieldIncidence;
  if (status) cloud.fields |= kFieldStatus;
  if (estimated) cloud.fields |= kFieldEstimatedNormal;
  cloud.Resize(h.points);
  for (size_t i = 0; i < h.points; ++i) {
    const char* rec = data.data() + i * h.stride;
    const auto f = [&](const PcdField* p) { return static_cast<float>(ReadScalar(rec + p->offset, *p)); };
    const auto u = [&](const PcdField* p) { return static_cast<uint32_t>(ReadScalar(rec + p->offset, *p)); };
    const auto v = [&](const Vec3Fields& v3) { return Eigen::Vector3f(f(v3.x), f(v3.y), f(v3.z)); };
    cloud.positions[i] = {f(x), f(y), f(z)};
    if (normal) cloud.normals[i] = v(normal);
    if (range) cloud.ranges[i] = f(range);
    if (intensity) cloud.intensities[i] = f(intensity);
    if (instance) cloud.instance_ids[i] = u(instance);
    if (pixel) cloud.pixels[i] = u(pixel);
    if (clean) cloud.clean_positions[i] = v(clean);
    if (incidence) cloud.incidence_angles[i] = f(incidence);
    if (status) cloud.statuses[i] = static_cast<uint8_t>(u(status));
    if (estimated) cloud.estimated_normals[i] = v(estimated);
  }
  return cloud;
}

}  // namespace vscan::render
