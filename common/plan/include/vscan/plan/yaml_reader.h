#pragma once
// Typed reads from a YAML document whose errors carry "source:line: key.path: what".

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "vscan/common/status.h"

namespace vscan::plan {

// A node and the key path that leads to it ("viewpoints[2].target").
struct YamlAt {
  YAML::Node node;
  std::string path;
  // Where a missing node would have been: the enclosing map, for its line number.
  YAML::Mark mark;
};

class YamlReader {
 public:
  explicit YamlReader(std::string source) : source_(std::move(source)) {}

  // INVALID_ARGUMENT "source:line: path: what".
  Status Error(const YamlAt& at, const std::string& what) const;
  Status Error(const YAML::Mark& mark, const std::string& path, const std::string& what) const;

  // The child key of a map (may be undefined: check Has).
  static YamlAt Child(const YamlAt& map, const std::string& key);
  static YamlAt Item(const YamlAt& seq, size_t index);
  static bool Has(const YamlAt& at) { return at.node.IsDefined() && !at.node.IsNull(); }

  // at must be a map whose keys are all in allowed, each once.
  Status ExpectMap(const YamlAt& at, std::initializer_list<const char*> allowed) const;
  Status ExpectMap(const YamlAt& at, std::span<const char* const> allowed) const;
  // Sequence of at least min_size items.
  Status ExpectSequence(const YamlAt& at, size_t min_size) const;

  StatusOr<double> Number(const YamlAt& at) const;
  // A whole number in [min, max].
  StatusOr<uint64_t> Integer(const YamlAt& at, uint64_t min, uint64_t max) const;
  StatusOr<bool> Bool(const YamlAt& at) const;
  // A non-empty scalar.
  StatusOr<std::string> String(const YamlAt& at) const;
  // A sequence of exactly count numbers.
  StatusOr<std::vector<double>> Numbers(const YamlAt& at, size_t count) const;
  StatusOr<Eigen::Vector3d> Vector3(const YamlAt& at) const;
  // One number, or a list of at least one.
  StatusOr<std::vector<double>> NumberOrList(const YamlAt& at) const;
  // A string or a list of strings, joined with commas.
  StatusOr<std::string> StringOrList(const YamlAt& at) const;
  // "'text'", "a list", "a mapping" or "nothing", for messages.
  static std::string Describe(const YAML::Node& node);

 private:
  std::string source_;
};

// Every key path of a document (as YamlAt paths read: "a.b", "a[2]"; "" the root) and its mark.
std::map<std::string, YAML::Mark> KeyMarks(const YAML::Node& root);

// "a.b[2]" -> "a.b" -> "a" -> "".
std::string ParentKey(const std::string& path);

// The whole of a plan file (NOT_FOUND when it cannot be opened, DATA_LOSS when reading fails).
StatusOr<std::string> ReadPlanFile(const std::string& path);

// A plan document read by parse(root) (a StatusOr<Plan>), with plan.source and plan.key_marks
// set; YAML syntax and conversion errors carry "source:line:".
template <class Plan, class Parse>
StatusOr<Plan> ParsePlanDocument(const std::string& yaml, const std::string& source, Parse parse) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    return YamlReader(source).Error(e.mark, "", "not valid YAML: " + e.msg);
  }
  try {
    StatusOr<Plan> plan = parse(root);
    if (!plan.ok()) return plan.status();
    plan->source = source;
    plan->key_marks = KeyMarks(root);
    return plan;
  } catch (const YAML::Exception& e) {
    return YamlReader(source).Error(e.mark, "", e.msg);
  }
}

}  // namespace vscan::plan
