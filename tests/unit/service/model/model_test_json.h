#pragma once
// Reads the JSON reports jobs write (model.json), so that tests check their figures by key.

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace vscan::service::testing {

class JsonValue {
 public:
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };

  // Parses text; a malformed document fails the calling test and yields null.
  static JsonValue Parse(const std::string& text);

  Kind kind() const { return kind_; }
  bool Has(const std::string& key) const { return kind_ == Kind::kObject && members_.count(key) > 0; }
  // A missing key or index fails the calling test and yields null.
  const JsonValue& operator[](const std::string& key) const;
  const JsonValue& operator[](size_t index) const;
  size_t size() const { return kind_ == Kind::kArray ? items_.size() : members_.size(); }
  double number() const;
  bool boolean() const;
  const std::string& text() const;

 private:
  friend class JsonParser;
  Kind kind_ = Kind::kNull;
  bool bool_ = false;
  double number_ = 0;
  std::string text_;
  std::vector<JsonValue> items_;
  std::map<std::string, JsonValue> members_;
};

}  // namespace vscan::service::testing
