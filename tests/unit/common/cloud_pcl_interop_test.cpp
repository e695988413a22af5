// vscan's cloud files against PCL's own readers and writers: every field vscan writes comes back in
// PCL with its values, an organised scan is what PCL's organised algorithms expect, and the files PCL
// writes in each encoding read back in vscan.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include "vscan/common/cloud_io.h"
#include "vscan/common/organized_pcd.h"

namespace vscan {
namespace {

namespace fs = std::filesystem;

constexpr uint32_t kEveryField = kFieldsAll | kFieldsGroundTruth | kFieldEstimatedNormal;

class CloudPclInteropTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("vscan_pcl_interop_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

// A scan-like cloud: ids and pixels as a camera gives them (below 2^31), every status.
PointCloud ScanLikeCloud(size_t n) {
  PointCloud c;
  c.fields = kEveryField;
  c.Resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float f = static_cast<float>(i);
    c.positions[i] = {0.25f * f, -1.5f + 0.125f * f, 2.0f + 1.0f / (1.0f + f)};
    c.normals[i] = Eigen::Vector3f(1, f, 2).normalized();
    c.ranges[i] = 3.0f + 0.5f * f;
    c.intensities[i] = 0.75f / (1.0f + f);
    c.instance_ids[i] = static_cast<uint32_t>(i % 5 + 1000 * i);
    c.pixels[i] = static_cast<uint32_t>(640 * 480 - 1 - 17 * i);
    c.clean_positions[i] = c.positions[i] + Eigen::Vector3f(0.001f, -0.002f, 0.003f);
    c.incidence_angles[i] = 0.01f * f;
    c.statuses[i] = static_cast<uint8_t>(i % 9);
    c.estimated_normals[i] = Eigen::Vector3f(f, 1, 0).normalized();
  }
  return c;
}

// The value of field `name` of point i, as PCL holds it, converted to double.
double PclValue(const pcl::PCLPointCloud2& cloud, const std::string& name, size_t i) {
  for (const pcl::PCLPointField& f : cloud.fields) {
    if (f.name != name) continue;
    const uint8_t* p = cloud.data.data() + i * cloud.point_step + f.offset;
    switch (f.datatype) {
      case pcl::PCLPointField::FLOAT32: { float v; std::memcpy(&v, p, 4); return v; }
      case pcl::PCLPointField::FLOAT64: { double v; std::memcpy(&v, p, 8); return v; }
      case pcl::PCLPointField::INT32: { int32_t v; std::memcpy(&v, p, 4); return v; }
      case pcl::PCLPointField::UINT32: { uint32_t v; std::memcpy(&v, p, 4); return v; }
      case pcl::PCLPointField::UINT8: return *p;
      case pcl::PCLPointField::INT8: return static_cast<int8_t>(*p);
      default: ADD_FAILURE() << name << ": datatype " << int(f.datatype); return NAN;
    }
  }
  ADD_FAILURE() << "PCL has no field '" << name << "'";
  return NAN;
}

// Every field of `c` compared with what PCL read, under the names of the file's format.
void ExpectPclHasEveryValue(const pcl::PCLPointCloud2& pcl_cloud, const PointCloud& c, bool ply) {
  ASSERT_EQ(size_t{pcl_cloud.width} * pcl_cloud.height, c.size());
  const auto vec3 = [&](const char* x, const char* y, const char* z, const std::vector<Eigen::Vector3f>& v,
                        size_t i) {
    EXPECT_EQ(PclValue(pcl_cloud, x, i), v[i].x()) << x << " of point " << i;
    EXPECT_EQ(PclValue(pcl_cloud, y, i), v[i].y()) << y << " of point " << i;
    EXPECT_EQ(PclValue(pcl_cloud, z, i), v[i].z()) << z << " of point " << i;
  };
  for (size_t i = 0; i < c.size(); ++i) {
    vec3("x", "y", "z", c.positions, i);
    // PCL's PLY reader names nx ny nz normal_x normal_y normal_z, as its PCD reader does.
    vec3("normal_x", "normal_y", "normal_z", c.normals, i);
    EXPECT_EQ(PclValue(pcl_cloud, "range", i), c.ranges[i]);
    EXPECT_EQ(PclValue(pcl_cloud, "intensity", i), c.intensities[i]);
    EXPECT_EQ(PclValue(pcl_cloud, "instance", i), c.instance_ids[i]);
    EXPECT_EQ(PclValue(pcl_cloud, "pixel", i), c.pixels[i]);
    vec3("clean_x", "clean_y", "clean_z", c.clean_positions, i);
    EXPECT_EQ(PclValue(pcl_cloud, "incidence", i), c.incidence_angles[i]);
    EXPECT_EQ(PclValue(pcl_cloud, "status", i), c.statuses[i]);
    if (ply) {
      vec3("enx", "eny", "enz", c.estimated_normals, i);
    } else {
      vec3("est_normal_x", "est_normal_y", "est_normal_z", c.estimated_normals, i);
    }
  }
}

TEST_F(CloudPclInteropTest, PclReadsEveryFieldOfVscansPly) {
  const PointCloud cloud = ScanLikeCloud(50);
  ASSERT_TRUE(WritePly(cloud, Path("scan.ply")).ok());
  pcl::PCLPointCloud2 back;
  ASSERT_EQ(pcl::io::loadPLYFile(Path("scan.ply"), back), 0);
  ExpectPclHasEveryValue(back, cloud, true);
}

TEST_F(CloudPclInteropTest, PclReadsEveryFieldOfVscansPcd) {
  const PointCloud cloud = ScanLikeCloud(50);
  ASSERT_TRUE(WritePcd(cloud, Path("scan.pcd")).ok());
  pcl::PCLPointCloud2 back;
  ASSERT_EQ(pcl::io::loadPCDFile(Path("scan.pcd"), back), 0);
  ExpectPclHasEveryValue(back, cloud, false);
}

TEST_F(CloudPclInteropTest, AnOrganisedScanIsARangeImageInPcl) {
  // Three points of a 4 x 3 image: pixel v * 4 + u.
  PointCloud cloud;
  cloud.fields = kFieldPosition | kFieldRange | kFieldPixel | kFieldInstanceId;
  cloud.Resize(3);
  cloud.positions = {{0.1f, 0.2f, 1.0f}, {-0.3f, 0.4f, 1.5f}, {0.5f, -0.6f, 2.0f}};
  cloud.ranges = {1.1f, 1.6f, 2.1f};
  cloud.pixels = {6, 0, 11};  // (u 2, v 1), (0, 0), (3, 2)
  cloud.instance_ids = {7, 8, 9};
  RangeImageLayout image;
  image.width = 4;
  image.height = 3;
  image.viewpoint = Eigen::Translation3d(1.0, -2.0, 0.5) *
                    Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  ASSERT_TRUE(WriteOrganizedPcd(cloud, image, Path("organised.pcd")).ok());

  pcl::PointCloud<pcl::PointXYZ> xyz;
  ASSERT_EQ(pcl::io::loadPCDFile(Path("organised.pcd"), xyz), 0);
  EXPECT_TRUE(xyz.isOrganized());
  EXPECT_EQ(xyz.width, 4u);
  EXPECT_EQ(xyz.height, 3u);
  EXPECT_FALSE(xyz.is_dense);
  EXPECT_EQ(xyz.at(2, 1).getVector3fMap(), cloud.positions[0]);
  EXPECT_EQ(xyz.at(0, 0).getVector3fMap(), cloud.positions[1]);
  EXPECT_EQ(xyz.at(3, 2).getVector3fMap(), cloud.positions[2]);
  EXPECT_TRUE(std::isnan(xyz.at(1, 0).x) && std::isnan(xyz.at(1, 0).y) && std::isnan(xyz.at(1, 0).z));
  const Eigen::Vector3d origin = xyz.sensor_origin_.head<3>().cast<double>();
  EXPECT_LT((origin - image.viewpoint.translation()).norm(), 1e-6);
  const Eigen::Quaterniond q(image.viewpoint.rotation());
  EXPECT_LT(xyz.sensor_orientation_.cast<double>().angularDistance(q), 1e-6);

  // The other fields sit at the same pixels; holes are NaN, or 0 for ids.
  pcl::PCLPointCloud2 all;
  ASSERT_EQ(pcl::io::loadPCDFile(Path("organised.pcd"), all), 0);
  EXPECT_EQ(PclValue(all, "range", 6), 1.1f);
  EXPECT_EQ(PclValue(all, "instance", 11), 9);
  EXPECT_EQ(PclValue(all, "pixel", 6), 6);
  EXPECT_EQ(PclValue(all, "pixel", 5), 5);
  EXPECT_TRUE(std::isnan(PclValue(all, "range", 5)));
  EXPECT_EQ(PclValue(all, "instance", 5), 0);

  // vscan reads it back as 12 points, the three at their pixels.
  const auto back = ReadPcd(Path("organised.pcd"));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->size(), 12u);
  EXPECT_EQ(back->positions[11], cloud.positions[2]);
  EXPECT_EQ(back->instance_ids[0], 8u);
}

TEST(OrganizeByPixel, RefusesWhatIsNoRangeImage) {
  PointCloud cloud;
  cloud.fields = kFieldPosition | kFieldPixel;
  cloud.Resize(2);
  cloud.pixels = {1, 1};
  EXPECT_EQ(OrganizeByPixel(cloud, 2, 2).status().code(), StatusCode::kInvalidArgument);  // one pixel twice
  cloud.pixels = {1, 4};
  const Status outside = OrganizeByPixel(cloud, 2, 2).status();
  EXPECT_EQ(outside.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(outside.message().find("cloud.pixels[1]"), std::string::npos) << outside.message();
  EXPECT_EQ(OrganizeByPixel(cloud, 0, 2).status().code(), StatusCode::kInvalidArgument);
  cloud.fields = kFieldPosition;
  cloud.Resize(2);
  EXPECT_EQ(OrganizeByPixel(cloud, 2, 2).status().code(), StatusCode::kInvalidArgument);  // no pixels
}

// A cloud in PCL's XYZ + intensity + normal type, values differing per point.
pcl::PointCloud<pcl::PointXYZINormal> PclCloud(size_t n) {
  pcl::PointCloud<pcl::PointXYZINormal> c;
  for (size_t i = 0; i < n; ++i) {
    pcl::PointXYZINormal p;
    const float f = static_cast<float>(i);
    p.x = 0.5f * f - 3.0f;
    p.y = 1.0f / (1.0f + f);
    p.z = 2.0f + 0.001f * f;
    p.intensity = 0.1f * f;
    p.normal_x = 0.0f;
    p.normal_y = 0.6f;
    p.normal_z = 0.8f;
    p.curvature = 0.0f;
    c.push_back(p);
  }
  return c;
}

TEST_F(CloudPclInteropTest, VscanReadsWhatPclWritesInEachEncoding) {
  const auto source = PclCloud(1000);
  ASSERT_EQ(pcl::io::savePCDFileASCII(Path("ascii.pcd"), source), 0);
  ASSERT_EQ(pcl::io::savePCDFileBinary(Path("binary.pcd"), source), 0);
  ASSERT_EQ(pcl::io::savePCDFileBinaryCompressed(Path("compressed.pcd"), source), 0);
  ASSERT_EQ(pcl::io::savePLYFileASCII(Path("ascii.ply"), source), 0);
  ASSERT_EQ(pcl::io::savePLYFileBinary(Path("binary.ply"), source), 0);
  for (const char* name : {"ascii.pcd", "binary.pcd", "compressed.pcd", "ascii.ply", "binary.ply"}) {
    SCOPED_TRACE(name);
    const auto cloud = ReadCloud(Path(name));
    ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
    ASSERT_EQ(cloud->size(), source.size());
    ASSERT_TRUE(cloud->Has(kFieldNormal));
    ASSERT_TRUE(cloud->Has(kFieldIntensity));
    // PCL's ASCII writers print 8 significant digits, so text values come back within float rounding.
    const bool text = std::string(name).starts_with("ascii");
    for (size_t i = 0; i < source.size(); ++i) {
      const auto& p = source[i];
      if (text) {
        EXPECT_NEAR(cloud->positions[i].x(), p.x, 1e-6f * (1 + std::abs(p.x)));
        EXPECT_NEAR(cloud->positions[i].y(), p.y, 1e-6f);
        EXPECT_NEAR(cloud->positions[i].z(), p.z, 1e-6f * 3);
        EXPECT_NEAR(cloud->intensities[i], p.intensity, 1e-5f);
      } else {
        EXPECT_EQ(cloud->positions[i], p.getVector3fMap());
        EXPECT_EQ(cloud->intensities[i], p.intensity);
      }
      EXPECT_NEAR((cloud->normals[i] - p.getNormalVector3fMap()).norm(), 0.0f, 1e-6f);
    }
  }
}

TEST_F(CloudPclInteropTest, AnOrganisedPclCloudReadsWithItsHoles) {
  pcl::PointCloud<pcl::PointXYZ> image(3, 2);
  for (size_t i = 0; i < image.size(); ++i) image[i] = pcl::PointXYZ(float(i), 1.0f, 2.0f);
  image.at(1, 1).x = image.at(1, 1).y = image.at(1, 1).z = std::numeric_limits<float>::quiet_NaN();
  image.is_dense = false;
  for (const auto& [name, save] :
       {std::pair{"ascii.pcd", 0}, std::pair{"binary.pcd", 1}, std::pair{"compressed.pcd", 2}}) {
    SCOPED_TRACE(name);
    pcl::PCDWriter writer;
    const int rc = save == 0   ? writer.writeASCII(Path(name), image)
                   : save == 1 ? writer.writeBinary(Path(name), image)
                               : writer.writeBinaryCompressed(Path(name), image);
    ASSERT_EQ(rc, 0);
    const auto cloud = ReadPcd(Path(name));
    ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
    ASSERT_EQ(cloud->size(), 6u);
    EXPECT_EQ(cloud->positions[5], Eigen::Vector3f(5, 1, 2));
    EXPECT_TRUE(cloud->positions[4].array().isNaN().all());
  }
}

}  // namespace
}  // namespace vscan
