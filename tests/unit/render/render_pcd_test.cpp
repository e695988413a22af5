#include <gtest/gtest.h>

#include "render_test_scenes.h"
#include "vscan_test/temp_dir.h"
#include "vscan/common/cloud_io.h"
#include "vscan/render/render_input.h"
#include "vscan_test/clouds.h"

namespace vscan::render {
namespace {

// `vscan render --color status` (and every other mode) must work on a .pcd as on a .ply.
TEST(PcdReadTest, ReadsBackEveryFieldCommonWrites) {
  vscan::test::TempDir dir;
  for (const uint32_t fields : {uint32_t{kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal},
                                uint32_t{kFieldPosition | kFieldStatus}}) {
    const PointCloud cloud = vscan::test::MakeCloud(fields, 50);
    const std::string path = (dir.path() / ("cloud-" + std::to_string(fields) + ".pcd")).string();
    ASSERT_TRUE(WritePcd(cloud, path).ok());
    const auto input = LoadRenderInput(path);
    ASSERT_TRUE(input.ok()) << input.status().message();
    vscan::test::ExpectSameCloud(input->cloud, cloud);
  }
}

}  // namespace
}  // namespace vscan::render
