#include "model_test_json.h"

#include <cstdlib>

#include <gtest/gtest.h>

namespace vscan::service::testing {

class JsonParser {
 public:
  explicit JsonParser(const std::string& text) : s_(text) {}

  bool Document(JsonValue& out) {
    if (!Value(out)) return false;
    Space();
    return i_ == s_.size();
  }

 private:
  void Space() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool Literal(const char* word) {
    const std::string w(word);
    if (s_.compare(i_, w.size(), w) != 0) return false;
    i_ += w.size();
    return true;
  }
  bool String(std::string& out) {
    if (s_[i_] != '"') return false;
    ++i_;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (s_[i_] == '\\') {
        ++i_;
        if (i_ >= s_.size()) return false;
        const char c = s_[i_];
        if (c == 'u') {
          if (i_ + 4 >= s_.size()) return false;
          out += static_cast<char>(std::strtol(s_.substr(i_ + 1, 4).c_str(), nullptr, 16));
          i_ += 4;
        } else {
          out += c == 'n' ? '\n' : c == 't' ? '\t' : c;
        }
      } else {
        out += s_[i_];
      }
      ++i_;
    }
    if (i_ >= s_.size()) return false;
    ++i_;
    return true;
  }
  bool Value(JsonValue& out) {
    Space();
    if (i_ >= s_.size()) return false;
    const char c = s_[i_];
    if (c == '{') {
      out.kind_ = JsonValue::Kind::kObject;
      ++i_;
      Space();
      if (s_[i_] == '}') return ++i_, true;
      for (;;) {
        Space();
        std::string key;
        if (!String(key)) return false;
        Space();
        if (s_[i_++] != ':') return false;
        if (!Value(out.members_[key])) return false;
        Space();
        if (s_[i_] == ',') {
          ++i_;
          continue;
        }
        return s_[i_++] == '}';
      }
    }
    if (c == '[') {
      out.kind_ = JsonValue::Kind::kArray;
      ++i_;
      Space();
      if (s_[i_] == ']') return ++i_, true;
      for (;;) {
        out.items_.emplace_back();
        if (!Value(out.items_.back())) return false;
        Space();
        if (s_[i_] == ',') {
          ++i_;
          continue;
        }
        return s_[i_++] == ']';
      }
    }
    if (c == '"') {
      out.kind_ = JsonValue::Kind::kString;
      return String(out.text_);
    }
    if (Literal("true") || Literal("false")) {
      out.kind_ = JsonValue::Kind::kBool;
      out.bool_ = s_[i_ - 1] == 'e' && s_[i_ - 2] == 'u';
      return true;
    }
    if (Literal("null")) return true;
    char* end = nullptr;
    out.number_ = std::strtod(s_.c_str() + i_, &end);
    if (end == s_.c_str() + i_) return false;
    out.kind_ = JsonValue::Kind::kNumber;
    i_ = static_cast<size_t>(end - s_.c_str());
    return true;
  }

  const std::string& s_;
  size_t i_ = 0;
};

namespace {
const JsonValue& Null() {
  static const JsonValue null;
  return null;
}
}  // namespace

JsonValue JsonValue::Parse(const std::string& text) {
  JsonValue value;
  if (!JsonParser(text).Document(value)) {
    ADD_FAILURE() << "not JSON: " << text.substr(0, 200);
    return JsonValue();
  }
  return value;
}

const JsonValue& JsonValue::operator[](const std::string& key) const {
  const auto it = members_.find(key);
  if (kind_ != Kind::kObject || it == members_.end()) {
    ADD_FAILURE() << "no key '" << key << "'";
    return Null();
  }
  return it->second;
}

const JsonValue& JsonValue::operator[](size_t index) const {
  if (kind_ != Kind::kArray || index >= items_.size()) {
    ADD_FAILURE() << "no item " << index;
    return Null();
  }
  return items_[index];
}

double JsonValue::number() const {
  EXPECT_EQ(kind_, Kind::kNumber);
  return number_;
}

bool JsonValue::boolean() const {
  EXPECT_EQ(kind_, Kind::kBool);
  return bool_;
}

const std::string& JsonValue::text() const {
  EXPECT_EQ(kind_, Kind::kString);
  return text_;
}

}  // namespace vscan::service::testing
