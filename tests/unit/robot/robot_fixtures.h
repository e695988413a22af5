#pragma once
// Fixture robots from data/robots, loaded the way an upload arrives: a URDF plus its files.

#include <string>
#include <vector>

#include "robot/chain.h"
#include "robot/urdf_bundle.h"

namespace vscan::robot::testing {

struct FixtureRobot {
  std::string name;  // "ur5" or "panda"
  std::string urdf_path;
  std::string base_link;
  std::string tip_link;
};

const std::vector<FixtureRobot>& FixtureRobots();
const FixtureRobot& Fixture(const std::string& name);

std::string ReadFile(const std::string& path);

// Every file of data/robots/<name>, with paths relative to that directory.
std::vector<BundleFile> FixtureBundleFiles(const std::string& name);

// The loaded bundle; aborts the test binary if the fixture does not load.
const UrdfBundle& FixtureBundle(const std::string& name);

// The fixture's suggested chain (SOURCE.md), optionally with a tool offset.
KinematicChain FixtureChain(const std::string& name, const Pose3& tip_from_tool = Pose3::Identity());

}  // namespace vscan::robot::testing
