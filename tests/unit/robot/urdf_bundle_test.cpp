#include "robot/urdf_bundle.h"

#include <gtest/gtest.h>

#include "robot_fixtures.h"

namespace vscan::robot {
namespace {

// A two-link arm whose second link shows mesh_filename.
std::string ArmUrdf(const std::string& mesh_filename) {
  return R"(<robot name="arm">
  <link name="base"/>
  <link name="arm"><visual><geometry><mesh filename=")" +
         mesh_filename + R"(" scale="0.001 0.001 0.001"/></geometry></visual></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>)";
}

StatusOr<UrdfBundle> LoadArm(const std::string& mesh_filename, std::vector<BundleFile> extra = {},
                             const std::string& urdf_path = "arm.urdf") {
  extra.push_back({urdf_path, ArmUrdf(mesh_filename)});
  return LoadUrdfBundle(urdf_path, std::move(extra));
}

void ExpectInvalidBundle(const Status& status, const std::string& fragment) {
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << status.ToString();
  EXPECT_NE(status.message().find(fragment), std::string::npos) << status.message();
}

TEST(BundlePaths, NormalisesWithinTheRoot) {
  EXPECT_EQ(NormalizeBundlePath("a//./b/../c.stl", "f").value(), "a/c.stl");
  EXPECT_EQ(ParentDirectory("a/b/c.stl"), "a/b");
  EXPECT_EQ(ParentDirectory("c.stl"), "");
  ExpectInvalidBundle(NormalizeBundlePath("../x.stl", "f").status(), "escapes");
  ExpectInvalidBundle(NormalizeBundlePath("a/../../x.stl", "f").status(), "escapes");
  ExpectInvalidBundle(NormalizeBundlePath("/etc/passwd", "f").status(), "absolute");
  ExpectInvalidBundle(NormalizeBundlePath("a\\..\\x", "f").status(), "backslash");
  ExpectInvalidBundle(NormalizeBundlePath("a/..", "f").status(), "root");
  ExpectInvalidBundle(NormalizeBundlePath("", "f").status(), "empty");
}

TEST(UrdfBundle, RefusesFilePathsThatEscapeNamingTheIndex) {
  std::vector<BundleFile> files = {{"arm.urdf", ArmUrdf("m.stl")}, {"../x.stl", "solid"}};
  ExpectInvalidBundle(LoadUrdfBundle("arm.urdf", files).status(), "files[1].path");
  files[1].path = "/etc/passwd";
  ExpectInvalidBundle(LoadUrdfBundle("arm.urdf", files).status(), "files[1].path");
  files[1].path = "./arm.urdf";
  ExpectInvalidBundle(LoadUrdfBundle("arm.urdf", files).status(), "same file as files[0]");
}

TEST(UrdfBundle, RefusesMeshReferencesThatEscape) {
  ExpectInvalidBundle(LoadArm("../x.stl").status(), "'../x.stl' escapes the bundle");
  ExpectInvalidBundle(LoadArm("../../x.stl", {}, "urdf/arm.urdf").status(), "'../../x.stl' escapes the bundle");
  ExpectInvalidBundle(LoadArm("meshes/../../x.stl").status(), "escapes the bundle");
  ExpectInvalidBundle(LoadArm("/etc/passwd").status(), "'/etc/passwd'");
  ExpectInvalidBundle(LoadArm("package://p/../../x").status(), "'package://p/../../x' escapes the bundle");
  ExpectInvalidBundle(LoadArm("file:///etc/passwd").status(), "file://");
  ExpectInvalidBundle(LoadArm("http://example.com/m.stl").status(), "scheme");
}

TEST(UrdfBundle, ResolvesRelativeMeshesFromTheUrdfDirectory) {
  StatusOr<UrdfBundle> bundle = LoadArm("../meshes/m.stl", {{"meshes/m.stl", "solid m"}}, "urdf/arm.urdf");
  ASSERT_TRUE(bundle.ok()) << bundle.status().ToString();
  ASSERT_EQ(bundle->meshes.size(), 1u);
  EXPECT_EQ(bundle->meshes[0].bundle_path, "meshes/m.stl");
  EXPECT_EQ(bundle->meshes[0].link, "arm");
  EXPECT_EQ(bundle->meshes[0].role, "visual");
  EXPECT_DOUBLE_EQ(bundle->meshes[0].scale.x(), 0.001);
  EXPECT_TRUE(bundle->warnings.empty());
}

TEST(UrdfBundle, PackageUrisPreferTheLongestMatchingSuffix) {
  StatusOr<UrdfBundle> bundle =
      LoadArm("package://pkg/meshes/m.stl", {{"meshes/m.stl", "short"}, {"pkg/meshes/m.stl", "long"}, {"m.stl", "x"}});
  ASSERT_TRUE(bundle.ok()) << bundle.status().ToString();
  EXPECT_EQ(bundle->meshes[0].bundle_path, "pkg/meshes/m.stl");
}

TEST(UrdfBundle, PandaPackageUrisResolveToItsCollisionMeshes) {
  const UrdfBundle& bundle = testing::FixtureBundle("panda");
  int collision = 0;
  for (const MeshReference& mesh : bundle.meshes) {
    if (mesh.role != "collision") continue;
    ++collision;
    EXPECT_EQ(mesh.uri.rfind("package://example-robot-data/robots/panda_description/meshes/collision/", 0), 0u);
    EXPECT_EQ(mesh.bundle_path.rfind("meshes/collision/", 0), 0u) << mesh.uri;
    EXPECT_EQ(bundle.files.count(mesh.bundle_path), 1u) << mesh.bundle_path;
  }
  EXPECT_EQ(collision, 9);  // link0-7 and the hand; the fingers' collision shapes are not meshes
  // The visual .dae files are not in the fixture: one warning each, nothing resolved.
  for (const MeshReference& mesh : bundle.meshes) {
    if (mesh.role == "visual") {
      EXPECT_TRUE(mesh.bundle_path.empty()) << mesh.uri;
    }
  }
  EXPECT_EQ(bundle.warnings.size(), bundle.meshes.size() - collision);
}

TEST(UrdfBundle, Ur5MissingMeshesAreWarningsNotErrors) {
  const UrdfBundle& bundle = testing::FixtureBundle("ur5");
  EXPECT_FALSE(bundle.meshes.empty());
  EXPECT_EQ(bundle.warnings.size(), bundle.meshes.size());
  EXPECT_NE(bundle.warnings.front().find("not in the bundle"), std::string::npos) << bundle.warnings.front();
  ASSERT_NE(bundle.model, nullptr);
}

TEST(UrdfBundle, ParseFailuresAreInvalidArgumentWithUrdfdomReason) {
  StatusOr<UrdfBundle> bundle = LoadUrdfBundle("a.urdf", {{"a.urdf", "<robot name='r'><link name='a'/><joint"}});
  ExpectInvalidBundle(bundle.status(), "urdf: ");
  StatusOr<UrdfBundle> no_robot = LoadUrdfBundle("a.urdf", {{"a.urdf", "<notarobot/>"}});
  ExpectInvalidBundle(no_robot.status(), "urdf: ");
  EXPECT_GT(no_robot.status().message().size(), std::string("urdf: ").size());
}

TEST(UrdfBundle, UrdfPathMustBeInTheBundle) {
  ExpectInvalidBundle(LoadUrdfBundle("missing.urdf", {{"a.urdf", ArmUrdf("m.stl")}}).status(), "urdf_path");
}

TEST(UrdfBundle, LimitsAreResourceExhausted) {
  std::vector<BundleFile> files = {{"arm.urdf", ArmUrdf("m.stl")}, {"m.stl", std::string(1000, 'x')}};
  EXPECT_EQ(LoadUrdfBundle("arm.urdf", files, BundleLimits{.max_total_bytes = 1000, .max_files = 10}).status().code(),
            StatusCode::kResourceExhausted);
  EXPECT_EQ(LoadUrdfBundle("arm.urdf", files, BundleLimits{.max_total_bytes = 1 << 20, .max_files = 1}).status().code(),
            StatusCode::kResourceExhausted);
  EXPECT_TRUE(LoadUrdfBundle("arm.urdf", files, BundleLimits{.max_total_bytes = 1 << 20, .max_files = 2}).ok());
}

}  // namespace
}  // namespace vscan::robot
