#include "fixture_parts.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "geometry/mesh_import.h"

namespace vscan::physics::test {
namespace {

PartType Load(const std::string& file, double metres_per_unit, const std::string& name, size_t count) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/" + file, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  auto mesh = geometry::ImportMesh(bytes.str(), geometry::MeshFileFormat::kStl, metres_per_unit);
  if (!mesh.ok()) throw std::runtime_error(file + ": " + mesh.status().ToString());
  PartType part;
  part.name = name;
  part.mesh = std::move(*mesh);
  part.count = count;
  return part;
}

}  // namespace

PartType AngleBlock(size_t count) { return Load("angle_block.STL", 0.0254, "angle_block", count); }
PartType RoundPin(size_t count) { return Load("round.stl", 0.0013, "round", count); }

}  // namespace vscan::physics::test
