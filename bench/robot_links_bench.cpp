// Robot links in scans and collision checks: what one new arm configuration costs with the bunny
// and a UR5 whose links are boxes (the stored UR5 bundle has no meshes).
//   prepare: the Embree scene of bunny + link meshes, built as PrepareScanTarget does for a
//            joint configuration it has not cached;
//   collide: one Bullet check of the arm against the bunny and itself (shapes cached).

#include <benchmark/benchmark.h>

#include <fstream>
#include <random>
#include <sstream>

#include <urdf_model/model.h>

#include "bench_meshes.h"
#include "raycast/raycast_scene.h"
#include "robot/urdf_bundle.h"
#include "robot/urdf_chain.h"
#include "robot_registry/link_collision.h"
#include "robot_registry/link_geometry.h"

namespace vscan {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream out;
  out << in.rdbuf();
  return out.str();
}

// A box from the link origin to its child's joint origin, 4 cm thick.
TriangleMesh SpanBox(const Eigen::Vector3d& to) {
  const Eigen::Vector3f lo = (to.cwiseMin(Eigen::Vector3d::Zero()).array() - 0.04).cast<float>();
  const Eigen::Vector3f hi = (to.cwiseMax(Eigen::Vector3d::Zero()).array() + 0.04).cast<float>();
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

struct Fixture {
  Fixture() {
    bunny = std::make_shared<const TriangleMesh>(bench::ReadAsciiPly(std::string(VSCAN_DATA_DIR) +
                                                              "/meshes/bunny/bunny_zipper_res2.ply"));
    Pose3 bunny_pose = Pose3::Identity();
    bunny_pose.translation() = Eigen::Vector3d(0.5, 0.3, 0.0);
    scene.push_back({bunny, bunny_pose, 3.0, 1});
    auto bundle = robot::LoadUrdfBundle("ur5.urdf", {{"ur5.urdf", ReadFile(std::string(VSCAN_DATA_DIR) +
                                                                             "/robots/ur5/ur5_robot.urdf")}});
    chain = std::make_shared<robot::KinematicChain>(*robot::BuildChain(*bundle->model, {"base_link", "tool0", {}}));
    // Every mesh reference reads as the box spanning its link to the link's first child joint.
    robot_registry::LinkMeshImporter import = [&](std::string_view, std::string_view) -> StatusOr<TriangleMesh> {
      return InvalidArgument("unused");
    };
    links = *robot_registry::LoadRobotLinks(*bundle, *chain, import);
    for (size_t i = 0; i < links.names.size(); ++i) {
      const auto link = bundle->model->getLink(links.names[i]);
      if (link->child_joints.empty()) continue;
      const auto& p = link->child_joints.front()->parent_to_joint_origin_transform.position;
      const auto box = std::make_shared<const TriangleMesh>(SpanBox({p.x, p.y, p.z}));
      links.visual[i] = {{box, Pose3::Identity()}};
      links.collision[i] = links.visual[i];
    }
    links.allowed_contacts = robot_registry::AllowedLinkContacts(links, shapes);
    obstacles.push_back({"object 'bunny'", {{bunny, bunny_pose, Eigen::Vector3d::Constant(3.0)}}});
  }

  Eigen::VectorXd Random() { return robot::RandomJointPositions(*chain, rng); }

  std::shared_ptr<const TriangleMesh> bunny;
  std::vector<raycast::SceneInstance> scene;
  std::shared_ptr<robot::KinematicChain> chain;
  robot_registry::RobotLinks links;
  std::vector<robot_registry::Obstacle> obstacles;
  std::shared_ptr<collision::ShapeCache> shapes = std::make_shared<collision::ShapeCache>();
  std::mt19937_64 rng{7};
};

Fixture& Shared() {
  static Fixture fixture;
  return fixture;
}

void BM_PrepareLinksVisibleTarget(benchmark::State& state) {
  Fixture& f = Shared();
  for (auto _ : state) {
    const std::vector<Pose3> poses = robot_registry::LinkPoses(f.links, f.Random());
    std::vector<raycast::SceneInstance> instances = f.scene;
    for (size_t i = 0; i < f.links.names.size(); ++i) {
      for (const auto& shape : f.links.visual[i]) {
        instances.push_back({shape.mesh, poses[i] * shape.link_from_shape, 1.0, 0x80000000u + uint32_t(i) + 1});
      }
    }
    auto built = raycast::RaycastScene::Build(instances);
    benchmark::DoNotOptimize(built);
  }
  state.counters["triangles"] = static_cast<double>(f.bunny->triangles.size());
}
BENCHMARK(BM_PrepareLinksVisibleTarget)->Unit(benchmark::kMillisecond);

void BM_CollisionCheckPerConfiguration(benchmark::State& state) {
  Fixture& f = Shared();
  int64_t contacts = 0;
  for (auto _ : state) {
    auto found = robot_registry::FindLinkContact(f.links, f.links.allowed_contacts, Pose3::Identity(), f.Random(),
                                                f.obstacles, f.shapes);
    contacts += found.ok() && found->has_value();
  }
  state.counters["colliding_fraction"] =
      benchmark::Counter(static_cast<double>(contacts), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_CollisionCheckPerConfiguration)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace vscan

BENCHMARK_MAIN();
