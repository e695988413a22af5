#pragma once
// A bin plan: one YAML file that names the scene, the bin and the parts (mesh files with their
// units, or uploaded meshes) of a bin fill. Parsing needs no server; every error names the file,
// the line and the key path ("plan.yaml:9: parts[1].count: ...").

#include <yaml-cpp/mark.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "vscan/common/status.h"
#include "vscan/v1/job.pb.h"

namespace vscan::cli {

struct BinPlanPart {
  // A mesh file to upload (resolved against the plan's directory) in unit, or an uploaded mesh.
  std::filesystem::path mesh;
  v1::LengthUnit unit = v1::LENGTH_UNIT_UNSPECIFIED;
  std::string mesh_id;
};

struct BinPlan {
  std::string name;
  // The scene by name (used when one has it, else created) or by id.
  std::string scene_name;
  std::string scene_id;
  // parts[i] gives spec.parts(i).mesh_id when the plan runs.
  std::vector<BinPlanPart> parts;
  // A bin given as a mesh (spec.bin_mesh); gives spec.bin_mesh.mesh_id when the plan runs.
  std::optional<BinPlanPart> bin_mesh;
  // scene_id and the parts' mesh ids are filled in when the plan runs.
  v1::BinFillSpec spec;
  std::string source;
  std::map<std::string, YAML::Mark> key_marks;
};

StatusOr<BinPlan> ParseBinPlan(const std::string& yaml, const std::string& source,
                               const std::filesystem::path& base_dir);
// Reads path (NOT_FOUND when it cannot be read) and parses it relative to its directory.
StatusOr<BinPlan> LoadBinPlan(const std::string& path);

// "source:line: key: what" for a server error naming a spec field the plan sets ("spec.parts[1].count"),
// nullopt otherwise.
std::optional<std::string> LocateInBinPlan(const BinPlan& plan, const Status& status);

}  // namespace vscan::cli
