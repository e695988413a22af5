#include "robot_fixtures.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "robot/urdf_chain.h"

namespace vscan::robot::testing {
namespace {

[[noreturn]] void Die(const std::string& message) {
  std::fprintf(stderr, "robot fixture: %s\n", message.c_str());
  std::abort();
}

}  // namespace

const std::vector<FixtureRobot>& FixtureRobots() {
  static const std::vector<FixtureRobot> robots = {
      {"ur5", "ur5_robot.urdf", "base_link", "tool0"},
      {"panda", "panda.urdf", "panda_link0", "panda_link8"},
  };
  return robots;
}

const FixtureRobot& Fixture(const std::string& name) {
  for (const FixtureRobot& robot : FixtureRobots()) {
    if (robot.name == name) return robot;
  }
  Die("no fixture robot " + name);
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Die("cannot read " + path);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::vector<BundleFile> FixtureBundleFiles(const std::string& name) {
  const std::filesystem::path root = std::filesystem::path(VSCAN_DATA_DIR) / "robots" / name;
  std::vector<BundleFile> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    files.push_back({std::filesystem::relative(entry.path(), root).generic_string(), ReadFile(entry.path().string())});
  }
  return files;
}

const UrdfBundle& FixtureBundle(const std::string& name) {
  static std::map<std::string, std::unique_ptr<UrdfBundle>> cache;
  auto& slot = cache[name];
  if (slot == nullptr) {
    StatusOr<UrdfBundle> bundle = LoadUrdfBundle(Fixture(name).urdf_path, FixtureBundleFiles(name));
    if (!bundle.ok()) Die(bundle.status().ToString());
    slot = std::make_unique<UrdfBundle>(std::move(bundle).value());
  }
  return *slot;
}

KinematicChain FixtureChain(const std::string& name, const Pose3& tip_from_tool) {
  const FixtureRobot& robot = Fixture(name);
  StatusOr<KinematicChain> chain =
      BuildChain(*FixtureBundle(name).model, ChainSpec{robot.base_link, robot.tip_link, tip_from_tool});
  if (!chain.ok()) Die(chain.status().ToString());
  return std::move(chain).value();
}

}  // namespace vscan::robot::testing
