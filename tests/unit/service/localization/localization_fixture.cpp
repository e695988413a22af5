#include "localization_fixture.h"

#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

namespace vscan::service::testing {
namespace {

std::string StorePart(ServiceWorld& world, const char* file, double metres_per_unit) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/" + file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  scenes::MeshUpload upload;
  upload.name = file;
  upload.format = geometry::MeshFileFormat::kStl;
  upload.metres_per_unit = metres_per_unit;
  auto stored = world.context().registry.AddMesh(bytes, upload);
  EXPECT_TRUE(stored.ok()) << file << ": " << stored.status().ToString();
  return stored.ok() ? stored->mesh_id : "";
}

}  // namespace

std::array<std::string, 3> StoreFixtureParts(ServiceWorld& world) {
  return {StorePart(world, "angle_block.STL", 0.0254), StorePart(world, "round.stl", 0.01),
          StorePart(world, "plate_holes.STL", 0.001)};
}

}  // namespace vscan::service::testing
