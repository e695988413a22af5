#include "vscan_test/clouds.h"

#include <gtest/gtest.h>

namespace vscan::test {

PointCloud MakeCloud(uint32_t fields, size_t n) {
  PointCloud c;
  c.fields = fields;
  c.Resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float f = static_cast<float>(i);
    c.positions[i] = {f * 0.5f, -f, 1e-3f * f + 0.125f};
    if (c.Has(kFieldNormal)) c.normals[i] = Eigen::Vector3f(1, f, -2).normalized();
    if (c.Has(kFieldRange)) c.ranges[i] = 1.0f / (f + 1);
    if (c.Has(kFieldIntensity)) c.intensities[i] = 0.25f * f;
    if (c.Has(kFieldInstanceId)) c.instance_ids[i] = static_cast<uint32_t>(i % 7);
    if (c.Has(kFieldPixel)) c.pixels[i] = 0xFFFFFF00u + static_cast<uint32_t>(i % 256);
    if (c.Has(kFieldCleanPosition)) c.clean_positions[i] = c.positions[i] + Eigen::Vector3f(1e-3f, 0, -1e-3f * f);
    if (c.Has(kFieldIncidence)) c.incidence_angles[i] = 1.5f / (f + 1);
    if (c.Has(kFieldStatus)) c.statuses[i] = static_cast<uint8_t>(1 + i % 8);  // every PointStatus but unspecified
    if (c.Has(kFieldEstimatedNormal)) c.estimated_normals[i] = Eigen::Vector3f(-2, 1, f).normalized();
  }
  return c;
}

void ExpectSameCloud(const PointCloud& a, const PointCloud& b) {
  EXPECT_EQ(a.fields, b.fields);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.ranges, b.ranges);
  EXPECT_EQ(a.intensities, b.intensities);
  EXPECT_EQ(a.instance_ids, b.instance_ids);
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_EQ(a.clean_positions, b.clean_positions);
  EXPECT_EQ(a.incidence_angles, b.incidence_angles);
  EXPECT_EQ(a.statuses, b.statuses);
  EXPECT_EQ(a.estimated_normals, b.estimated_normals);
}

}  // namespace vscan::test
