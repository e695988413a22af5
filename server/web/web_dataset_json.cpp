#include "web/web_dataset_json.h"

#include <charconv>
#include <cmath>
#include <tuple>

#include <fmt/format.h>

#include "vscan/common/json_quote.h"

namespace vscan::web {
namespace {

constexpr int kMaxDepth = 64;

class Reader {
 public:
  Reader(std::string_view text, std::string_view what) : text_(text), what_(what) {}

  // Reads one value into out, or only steps over it when out is null.
  Status Value(JsonValue* out, int depth) {
    if (depth > kMaxDepth) return Fail("nested too deeply");
    SkipSpace();
    if (at_ >= text_.size()) return Fail("ends early");
    const char c = text_[at_];
    if (c == '{') return Object(out, depth);
    if (c == '[') return Array(out, depth);
    if (c == '"') {
      std::string text;
      RETURN_IF_ERROR(String(out ? &text : nullptr));
      if (out) {
        out->kind = JsonValue::Kind::kString;
        out->text = std::move(text);
      }
      return Status::Ok();
    }
    for (const auto& [word, kind, boolean] : {std::tuple{"true", JsonValue::Kind::kBool, true},
                                              std::tuple{"false", JsonValue::Kind::kBool, false},
                                              std::tuple{"null", JsonValue::Kind::kNull, false}}) {
      if (text_.substr(at_).starts_with(word)) {
        at_ += std::string_view(word).size();
        if (out) {
          out->kind = kind;
          out->boolean = boolean;
        }
        return Status::Ok();
      }
    }
    return Number(out);
  }

  // Steps into the top-level object and reads the member key, skipping the others.
  StatusOr<std::optional<JsonValue>> Member(std::string_view key) {
    SkipSpace();
    if (!Take('{')) return Fail("is not an object");
    std::optional<JsonValue> found;
    SkipSpace();
    if (Take('}')) return found;
    while (true) {
      std::string name;
      SkipSpace();
      RETURN_IF_ERROR(String(&name));
      SkipSpace();
      if (!Take(':')) return Fail("expects ':'");
      if (!found && name == key) {
        found.emplace();
        RETURN_IF_ERROR(Value(&*found, 1));
      } else {
        RETURN_IF_ERROR(Value(nullptr, 1));
      }
      SkipSpace();
      if (Take('}')) return found;
      if (!Take(',')) return Fail("expects ',' or '}'");
    }
  }

  Status End() {
    SkipSpace();
    return at_ == text_.size() ? Status::Ok() : Fail("has text after its value");
  }

 private:
  Status Fail(std::string_view why) const {
    return DataLoss(fmt::format("{}: not JSON as written: {} (byte {})", what_, why, at_));
  }
  void SkipSpace() {
    while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\n' || text_[at_] == '\r' || text_[at_] == '\t')) {
      ++at_;
    }
  }
  bool Take(char c) {
    if (at_ < text_.size() && text_[at_] == c) {
      ++at_;
      return true;
    }
    return false;
  }

  Status Object(JsonValue* out, int depth) {
    ++at_;
    if (out) out->kind = JsonValue::Kind::kObject;
    SkipSpace();
    if (Take('}')) return Status::Ok();
    while (true) {
      SkipSpace();
      std::string name;
      RETURN_IF_ERROR(String(out ? &name : nullptr));
      SkipSpace();
      if (!Take(':')) return Fail("expects ':'");
      JsonValue value;
      RETURN_IF_ERROR(Value(out ? &value : nullptr, depth + 1));
      if (out) out->members.emplace_back(std::move(name), std::move(value));
      SkipSpace();
      if (Take('}')) return Status::Ok();
      if (!Take(',')) return Fail("expects ',' or '}'");
    }
  }

  Status Array(JsonValue* out, int depth) {
    ++at_;
    if (out) out->kind = JsonValue::Kind::kArray;
    SkipSpace();
    if (Take(']')) return Status::Ok();
    while (true) {
      JsonValue value;
      RETURN_IF_ERROR(Value(out ? &value : nullptr, depth + 1));
      if (out) out->items.push_back(std::move(value));
      SkipSpace();
      if (Take(']')) return Status::Ok();
      if (!Take(',')) return Fail("expects ',' or ']'");
    }
  }

  // The files' strings are keys and names: escapes other than \uXXXX are kept, \uXXXX below 0x80
  // decoded, others refused (the writer never makes them).
  Status String(std::string* out) {
    if (!Take('"')) return Fail("expects a string");
    while (at_ < text_.size()) {
      const char c = text_[at_++];
      if (c == '"') return Status::Ok();
      if (static_cast<unsigned char>(c) < 0x20) return Fail("has a control character in a string");
      if (c != '\\') {
        if (out) *out += c;
        continue;
      }
      if (at_ >= text_.size()) break;
      const char e = text_[at_++];
      char decoded = 0;
      switch (e) {
        case '"': case '\\': case '/': decoded = e; break;
        case 'b': decoded = '\b'; break;
        case 'f': decoded = '\f'; break;
        case 'n': decoded = '\n'; break;
        case 'r': decoded = '\r'; break;
        case 't': decoded = '\t'; break;
        case 'u': {
          unsigned code = 0;
          if (at_ + 4 > text_.size()) return Fail("ends in an escape");
          const auto [end, error] = std::from_chars(text_.data() + at_, text_.data() + at_ + 4, code, 16);
          if (error != std::errc() || end != text_.data() + at_ + 4 || code >= 0x80) {
            return Fail("has an escape it does not read");
          }
          at_ += 4;
          decoded = static_cast<char>(code);
          break;
        }
        default: return Fail("has an unknown escape");
      }
      if (out) *out += decoded;
    }
    return Fail("ends in a string");
  }

  Status Number(JsonValue* out) {
    const size_t start = at_;
    while (at_ < text_.size()) {
      const char c = text_[at_];
      if ((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E') {
        ++at_;
      } else {
        break;
      }
    }
    double value = 0;
    const auto [end, error] = std::from_chars(text_.data() + start, text_.data() + at_, value);
    if (at_ == start || error != std::errc() || end != text_.data() + at_) return Fail("has a bad value");
    if (out) {
      out->kind = JsonValue::Kind::kNumber;
      out->number = value;
    }
    return Status::Ok();
  }

  std::string_view text_;
  std::string_view what_;
  size_t at_ = 0;
};

}  // namespace

const JsonValue* JsonValue::Find(std::string_view key) const {
  if (kind != Kind::kObject) return nullptr;
  for (const auto& [name, value] : members) {
    if (name == key) return &value;
  }
  return nullptr;
}

StatusOr<JsonValue> ParseJson(std::string_view text, std::string_view what) {
  Reader reader(text, what);
  JsonValue value;
  RETURN_IF_ERROR(reader.Value(&value, 0));
  RETURN_IF_ERROR(reader.End());
  return value;
}

StatusOr<std::optional<JsonValue>> ParseJsonMember(std::string_view text, std::string_view key, std::string_view what) {
  Reader reader(text, what);
  ASSIGN_OR_RETURN(std::optional<JsonValue> found, reader.Member(key));
  RETURN_IF_ERROR(reader.End());
  return found;
}

void AppendJson(std::string& out, const JsonValue& value) {
  switch (value.kind) {
    case JsonValue::Kind::kNull: out += "null"; return;
    case JsonValue::Kind::kBool: out += value.boolean ? "true" : "false"; return;
    case JsonValue::Kind::kNumber:
      out += std::isfinite(value.number) ? fmt::format("{}", value.number) : "null";
      return;
    case JsonValue::Kind::kString: out += JsonQuote(value.text); return;
    case JsonValue::Kind::kArray:
      out += '[';
      for (size_t i = 0; i < value.items.size(); ++i) {
        if (i) out += ',';
        AppendJson(out, value.items[i]);
      }
      out += ']';
      return;
    case JsonValue::Kind::kObject:
      out += '{';
      for (size_t i = 0; i < value.members.size(); ++i) {
        if (i) out += ',';
        out += JsonQuote(value.members[i].first);
        out += ':';
        AppendJson(out, value.members[i].second);
      }
      out += '}';
      return;
  }
}

}  // namespace vscan::web
