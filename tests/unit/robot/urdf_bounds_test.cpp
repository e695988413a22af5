// Every URDF number that places geometry is bounded at upload (physical_limits.h).

#include <gtest/gtest.h>

#include "robot/urdf_bundle.h"

namespace vscan::robot {
namespace {

// base -> arm by joint j; arm shows geometry at visual_origin and collision_origin.
struct Arm {
  std::string joint_xyz = "0 0 0.1";
  std::string joint_rpy = "0 0 0";
  std::string joint_type = "revolute";
  std::string limits = "lower='-1' upper='1'";
  std::string visual_xyz = "0 0 0";
  std::string visual_geometry = "<box size='0.1 0.1 0.1'/>";
  std::string collision_xyz = "0 0 0";
  std::string collision_geometry = "<cylinder radius='0.05' length='0.2'/>";

  std::string Urdf() const {
    return "<robot name='r'><link name='base'/><link name='arm'>"
           "<visual><origin xyz='" + visual_xyz + "'/><geometry>" + visual_geometry + "</geometry></visual>"
           "<collision><origin xyz='" + collision_xyz + "'/><geometry>" + collision_geometry + "</geometry></collision>"
           "</link><joint name='j' type='" + joint_type + "'><parent link='base'/><child link='arm'/>"
           "<origin xyz='" + joint_xyz + "' rpy='" + joint_rpy + "'/><axis xyz='0 0 1'/>"
           "<limit " + limits + " effort='1' velocity='1'/></joint></robot>";
  }

  Status Load() const { return LoadUrdfBundle("r.urdf", {{"r.urdf", Urdf()}, {"m.stl", "solid m"}}).status(); }
};

void ExpectInvalidBounds(const Status& status, const std::string& fragment) {
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << status.ToString();
  EXPECT_NE(status.message().find(fragment), std::string::npos) << status.message();
}

TEST(UrdfBounds, ValuesAtTheBoundLoad) {
  Arm arm;
  arm.joint_xyz = "10000 -10000 0";
  arm.visual_xyz = "0 0 -10000";
  arm.visual_geometry = "<box size='10000 10000 10000'/>";
  arm.collision_geometry = "<mesh filename='m.stl' scale='-10000 1 0.001'/>";
  arm.joint_type = "prismatic";
  arm.limits = "lower='-10000' upper='10000'";
  const Status status = arm.Load();
  EXPECT_TRUE(status.ok()) << status.ToString();
}

TEST(UrdfBounds, JointOriginsAreBounded) {
  Arm arm;
  arm.joint_xyz = "1e300 0 0";
  ExpectInvalidBounds(arm.Load(), "joints['j'].origin.xyz: coordinates beyond");
  arm.joint_xyz = "0 0 -10000.5";
  ExpectInvalidBounds(arm.Load(), "joints['j'].origin.xyz");
}

TEST(UrdfBounds, NonNumericOrOverflowingValuesAreRefused) {
  for (const char* bad : {"nan 0 0", "inf 0 0", "1e400 0 0"}) {
    Arm arm;
    arm.joint_xyz = bad;
    EXPECT_EQ(arm.Load().code(), StatusCode::kInvalidArgument) << bad;
    arm = Arm();
    arm.joint_rpy = bad;
    EXPECT_EQ(arm.Load().code(), StatusCode::kInvalidArgument) << bad;
  }
}

TEST(UrdfBounds, HugeFiniteRpyIsStillARotation) {
  // urdfdom keeps rpy only as a unit quaternion: a huge angle is a valid, if pointless, rotation.
  Arm arm;
  arm.joint_rpy = "1e300 -1e300 3";
  const Status status = arm.Load();
  EXPECT_TRUE(status.ok()) << status.ToString();
}

TEST(UrdfBounds, VisualAndCollisionOriginsAreBounded) {
  Arm arm;
  arm.visual_xyz = "0 1e300 0";
  ExpectInvalidBounds(arm.Load(), "links['arm'].visual[0].origin.xyz");
  arm = Arm();
  arm.collision_xyz = "0 0 2e4";
  ExpectInvalidBounds(arm.Load(), "links['arm'].collision[0].origin.xyz");
}

TEST(UrdfBounds, PrimitiveSizesAreBounded) {
  Arm arm;
  arm.visual_geometry = "<box size='1 1e300 1'/>";
  ExpectInvalidBounds(arm.Load(), "links['arm'].visual[0].box.size");
  arm.visual_geometry = "<sphere radius='1e300'/>";
  ExpectInvalidBounds(arm.Load(), "links['arm'].visual[0].sphere.radius");
  arm = Arm();
  arm.collision_geometry = "<cylinder radius='0.1' length='1e300'/>";
  ExpectInvalidBounds(arm.Load(), "links['arm'].collision[0].cylinder.length");
  arm.collision_geometry = "<cylinder radius='1e300' length='1'/>";
  ExpectInvalidBounds(arm.Load(), "links['arm'].collision[0].cylinder.radius");
}

TEST(UrdfBounds, MeshScalesAreBounded) {
  Arm arm;
  arm.collision_geometry = "<mesh filename='m.stl' scale='1 1 1e300'/>";
  ExpectInvalidBounds(arm.Load(), "links['arm'].collision[0].mesh.scale");
  arm.collision_geometry = "<mesh filename='m.stl' scale='-2e4 1 1'/>";
  ExpectInvalidBounds(arm.Load(), "links['arm'].collision[0].mesh.scale");
}

TEST(UrdfBounds, PrismaticLimitsAreBounded) {
  Arm arm;
  arm.joint_type = "prismatic";
  arm.limits = "lower='0' upper='1e300'";
  ExpectInvalidBounds(arm.Load(), "joints['j'].limit");
  // Angles are not lengths: a revolute joint's limits are not bound here.
  arm.joint_type = "revolute";
  const Status status = arm.Load();
  EXPECT_TRUE(status.ok()) << status.ToString();
}

}  // namespace
}  // namespace vscan::robot
