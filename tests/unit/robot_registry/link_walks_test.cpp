// The walks over a robot's links stay bounded, and link geometry stays within the physical limits.

#include <gtest/gtest.h>

#include "robot/urdf_chain.h"
#include "robot_registry/link_collision.h"
#include "robot_registry/link_geometry.h"
#include "vscan/common/physical_limits.h"

namespace vscan::robot_registry {
namespace {

// Links a and b hang from each other: no checked URDF gives this, but the walks must still end.
RobotLinks LoopingLinks() {
  RobotLinks links;
  links.names = {"a", "b", "c"};
  links.joints.resize(3);
  links.joints[0].parent = 1;
  links.joints[1].parent = 0;
  links.joints[2].parent = 0;
  links.joints[2].parent_from_joint.translation() = Eigen::Vector3d(1, 0, 0);
  links.visual.resize(3);
  links.collision.resize(3);
  return links;
}

TEST(LinkWalks, PosesOfLoopingParentsEnd) {
  const std::vector<Pose3> poses = LinkPoses(LoopingLinks(), Eigen::VectorXd::Zero(0));
  ASSERT_EQ(poses.size(), 3u);
  for (const Pose3& pose : poses) EXPECT_TRUE(pose.matrix().allFinite());
}

TEST(LinkWalks, AllowedContactsOfLoopingParentsEnd) {
  const auto allowed = AllowedLinkContacts(LoopingLinks(), std::make_shared<collision::ShapeCache>());
  EXPECT_TRUE(allowed.contains({0, 1}));
}

TEST(LinkGeometry, ScaledMeshBeyondTheBoundIsLeftOutWithAWarning) {
  const std::string urdf =
      "<robot name='r'><link name='base'/><link name='arm'><visual><geometry><mesh filename='m.stl' "
      "scale='3 3 3'/></geometry></visual></link><joint name='j' type='revolute'><parent link='base'/>"
      "<child link='arm'/><axis xyz='0 0 1'/><limit lower='-1' upper='1' effort='1' velocity='1'/></joint></robot>";
  auto bundle = robot::LoadUrdfBundle("r.urdf", {{"r.urdf", urdf}, {"m.stl", "solid m"}});
  ASSERT_TRUE(bundle.ok()) << bundle.status().ToString();
  auto chain = robot::BuildChain(*bundle->model, {});
  ASSERT_TRUE(chain.ok()) << chain.status().ToString();
  // A mesh within the bound on its own, three times too large once scaled.
  const LinkMeshImporter import = [](std::string_view, std::string_view) -> StatusOr<TriangleMesh> {
    TriangleMesh mesh;
    const auto far = static_cast<float>(kMaxMeshCoordinateM * 0.5);
    mesh.vertices = {{0, 0, 0}, {far, 0, 0}, {0, far, 0}};
    mesh.triangles = {{0, 1, 2}};
    return mesh;
  };
  auto links = LoadRobotLinks(*bundle, *chain, import);
  ASSERT_TRUE(links.ok()) << links.status().ToString();
  const size_t arm = 0;  // names are sorted: arm, base
  ASSERT_EQ(links->names[arm], "arm");
  EXPECT_TRUE(links->visual[arm].empty());
  ASSERT_EQ(links->warnings.size(), 1u);
  EXPECT_NE(links->warnings[0].find("links['arm'].visual[0]"), std::string::npos) << links->warnings[0];
  EXPECT_NE(links->warnings[0].find("beyond"), std::string::npos) << links->warnings[0];
}

}  // namespace
}  // namespace vscan::robot_registry
