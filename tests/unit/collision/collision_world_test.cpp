#include "collision/collision_world.h"

#include <gtest/gtest.h>

#include "vscan_test/meshes.h"

namespace vscan::collision {
namespace {

// An axis-aligned box centred on the origin.
std::shared_ptr<const TriangleMesh> Box(double sx, double sy, double sz) {
  const Eigen::Vector3d half(0.5 * sx, 0.5 * sy, 0.5 * sz);
  return vscan::test::Share(vscan::test::MakeBox(-half, half));
}

Pose3 At(double x, double y, double z) {
  Pose3 pose = Pose3::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

Body Placed(BodyKind kind, std::shared_ptr<const TriangleMesh> mesh, const Pose3& pose) {
  Body body;
  body.kind = kind;
  body.meshes.push_back({std::move(mesh), pose, Eigen::Vector3d::Ones()});
  return body;
}

// A 0.2 m link cube beside a 0.4 m object cube; their faces are `gap` apart (negative: overlap).
std::optional<Contact> LinkBesideObject(double gap, const std::shared_ptr<ShapeCache>& cache) {
  CollisionWorld world(cache);
  EXPECT_TRUE(world.AddBody(Placed(BodyKind::kObject, Box(0.4, 0.4, 0.4), At(0, 0, 0))).ok());
  EXPECT_TRUE(world.AddBody(Placed(BodyKind::kLink, Box(0.2, 0.2, 0.2), At(0.2 + 0.1 + gap, 0.05, 0))).ok());
  return world.FirstContact();
}

TEST(CollisionWorld, OverlappingLinkAndObjectAreReportedLinkFirst) {
  auto cache = std::make_shared<ShapeCache>();
  const auto contact = LinkBesideObject(-0.02, cache);
  ASSERT_TRUE(contact.has_value());
  EXPECT_EQ(contact->first, 1u);
  EXPECT_EQ(contact->second, 0u);
  EXPECT_NEAR(contact->distance, -0.02, 0.002);
}

TEST(CollisionWorld, LinkOneCentimetreAwayIsClear) {
  auto cache = std::make_shared<ShapeCache>();
  EXPECT_FALSE(LinkBesideObject(0.01, cache).has_value());
  // The cached shapes give the same answers again.
  EXPECT_FALSE(LinkBesideObject(0.01, cache).has_value());
  EXPECT_TRUE(LinkBesideObject(-0.005, cache).has_value());
}

TEST(CollisionWorld, ScaledObjectGrowsIntoTheLink) {
  CollisionWorld world(std::make_shared<ShapeCache>());
  Body object = Placed(BodyKind::kObject, Box(0.4, 0.4, 0.4), At(0, 0, 0));
  ASSERT_TRUE(world.AddBody(Placed(BodyKind::kLink, Box(0.2, 0.2, 0.2), At(0.35, 0, 0))).ok());
  ASSERT_TRUE(world.AddBody(object).ok());
  EXPECT_FALSE(world.FirstContact().has_value());

  CollisionWorld grown(std::make_shared<ShapeCache>());
  object.meshes[0].scale = Eigen::Vector3d(1.5, 1, 1);  // faces now at x = +-0.3
  ASSERT_TRUE(grown.AddBody(Placed(BodyKind::kLink, Box(0.2, 0.2, 0.2), At(0.35, 0, 0))).ok());
  ASSERT_TRUE(grown.AddBody(object).ok());
  const auto contact = grown.FirstContact();
  ASSERT_TRUE(contact.has_value());
  EXPECT_NEAR(contact->distance, -0.05, 0.005);
}

TEST(CollisionWorld, LinkPairsAreTestedUnlessIgnoredAndObjectsNeverMeetEachOther) {
  CollisionWorld world(std::make_shared<ShapeCache>());
  ASSERT_EQ(*world.AddBody(Placed(BodyKind::kLink, Box(0.2, 0.2, 0.2), At(0, 0, 0))), 0u);
  ASSERT_EQ(*world.AddBody(Placed(BodyKind::kLink, Box(0.2, 0.2, 0.2), At(0.15, 0, 0))), 1u);
  ASSERT_EQ(*world.AddBody(Placed(BodyKind::kLink, Box(0.2, 0.2, 0.2), At(0.30, 0, 0))), 2u);
  ASSERT_EQ(*world.AddBody(Placed(BodyKind::kObject, Box(1, 1, 0.1), At(0, 0, -2))), 3u);
  ASSERT_EQ(*world.AddBody(Placed(BodyKind::kObject, Box(1, 1, 0.1), At(0, 0, -2.05))), 4u);
  auto all = world.AllContacts();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].first, 0u);
  EXPECT_EQ(all[0].second, 1u);
  EXPECT_EQ(all[1].first, 1u);
  EXPECT_EQ(all[1].second, 2u);
  world.IgnorePair(1, 0);
  all = world.AllContacts();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].first, 1u);
  EXPECT_EQ(all[0].second, 2u);
}

TEST(CollisionWorld, BadMeshesAreRefusedNamingTheBody) {
  CollisionWorld world(std::make_shared<ShapeCache>());
  auto status = world.AddBody(Placed(BodyKind::kLink, std::make_shared<TriangleMesh>(), At(0, 0, 0)));
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(status.status().message().rfind("bodies[0].meshes[0].mesh:", 0), 0u) << status.status().message();
  Body scaled = Placed(BodyKind::kObject, Box(1, 1, 1), At(0, 0, 0));
  scaled.meshes[0].scale = Eigen::Vector3d(1, 0, 1);
  EXPECT_EQ(world.AddBody(scaled).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vscan::collision
