#include "raster_test_scenes.h"

#include <gtest/gtest.h>

#include "vscan_test/ascii_ply.h"
#include "vscan_test/meshes.h"

namespace vscan::raster::testing {

RasterRenderer* SharedRenderer() {
  static const auto renderer = RasterRenderer::Create();
  if (!renderer.ok()) {
    ADD_FAILURE() << renderer.status().ToString();
    return nullptr;
  }
  return renderer->get();
}

std::shared_ptr<const TriangleMesh> Bunny() {
  static const auto bunny =
      vscan::test::Share(vscan::test::ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply"));
  return bunny;
}

std::vector<int64_t> PointOfPixel(const PointCloud& cloud, const sensor::PinholeCamera& camera) {
  std::vector<int64_t> index(camera.pixel_count(), -1);
  for (size_t i = 0; i < cloud.pixels.size(); ++i) index[cloud.pixels[i]] = static_cast<int64_t>(i);
  return index;
}

}  // namespace vscan::raster::testing
