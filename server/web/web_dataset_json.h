#pragma once
// Reads the JSON files of a dataset (dataset.json, scene_camera.json, scene_gt.json,
// scene_gt_info.json) for the web view's /api/datasets, and writes parts of them back out.

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vscan/common/status.h"

namespace vscan::web {

struct JsonValue {
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };
  Kind kind = Kind::kNull;
  bool boolean = false;
  double number = 0;
  std::string text;                                        // kString
  std::vector<JsonValue> items;                            // kArray
  std::vector<std::pair<std::string, JsonValue>> members;  // kObject, in the file's order

  // The member named key of an object; null when absent or not an object.
  const JsonValue* Find(std::string_view key) const;
  bool IsNumber() const { return kind == Kind::kNumber; }
};

// DATA_LOSS naming what for text that is not one JSON value (or nests deeper than 64).
StatusOr<JsonValue> ParseJson(std::string_view text, std::string_view what);
// The member key of the object text holds, the other members skipped without being built (a
// scene's files hold every view; one is wanted). nullopt when there is none.
StatusOr<std::optional<JsonValue>> ParseJsonMember(std::string_view text, std::string_view key, std::string_view what);

// The value as compact JSON (numbers in their shortest exact form; non-finite as null).
void AppendJson(std::string& out, const JsonValue& value);

}  // namespace vscan::web
