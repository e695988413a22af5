#include "geometry/ply_header.h"

#include <array>
#include <charconv>
#include <cstdint>
#include <string>
#include <vector>

namespace vscan::geometry {
namespace {

constexpr size_t kMaxHeaderBytes = 64 * 1024;

struct ScalarType {
  std::string_view name;
  int bytes;
  bool integer;
};

constexpr std::array<ScalarType, 16> kScalarTypes = {{
    {"char", 1, true},    {"uchar", 1, true},   {"short", 2, true},  {"ushort", 2, true},
    {"int", 4, true},     {"uint", 4, true},    {"float", 4, false}, {"double", 8, false},
    {"int8", 1, true},    {"uint8", 1, true},   {"int16", 2, true},  {"uint16", 2, true},
    {"int32", 4, true},   {"uint32", 4, true},  {"float32", 4, false}, {"float64", 8, false},
}};

const ScalarType* FindType(std::string_view name) {
  for (const auto& type : kScalarTypes) {
    if (type.name == name) return &type;
  }
  return nullptr;
}

std::vector<std::string_view> Split(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

Status Bad(const std::string& why) { return InvalidArgument("mesh data: PLY header " + why); }

struct Element {
  uint64_t count = 0;
  uint64_t min_bytes = 0;  // binary size of one element with all its lists empty
  uint64_t properties = 0;
};

}  // namespace

Status CheckPlyHeader(std::string_view bytes) {
  std::vector<Element> elements;
  bool binary = false;
  bool have_format = false;
  size_t pos = 0;
  for (int line_number = 1;; ++line_number) {
    size_t eol = bytes.find('\n', pos);
    if (eol == std::string_view::npos || eol >= kMaxHeaderBytes) return Bad("has no end_header line");
    std::string_view line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    for (char c : line) {
      if ((c < 0x20 || c > 0x7e) && c != '\t') return Bad("line " + std::to_string(line_number) + " is not text");
    }
    std::vector<std::string_view> words = Split(line);

    if (line_number == 1) {
      if (words.size() != 1 || words[0] != "ply") return Bad("does not start with 'ply'");
      continue;
    }
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    const std::string where = " on line " + std::to_string(line_number);
    if (words[0] == "end_header") {
      if (words.size() != 1 || !have_format) return Bad("ends badly" + where);
      break;
    }
    if (words[0] == "format") {
      if (have_format || words.size() != 3 || words[2] != "1.0") return Bad("has a bad format line" + where);
      if (words[1] != "ascii" && words[1] != "binary_little_endian" && words[1] != "binary_big_endian") {
        return Bad("has an unknown format" + where);
      }
      binary = words[1] != "ascii";
      have_format = true;
    } else if (words[0] == "element") {
      Element element;
      if (words.size() != 3) return Bad("has a bad element line" + where);
      std::string_view count = words[2];
      auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), element.count);
      if (ec != std::errc() || end != count.data() + count.size() || element.count > UINT32_MAX) {
        return Bad("has a bad element count" + where);
      }
      elements.push_back(element);
    } else if (words[0] == "property") {
      if (elements.empty()) return Bad("has a property outside any element" + where);
      ++elements.back().properties;
      if (words.size() == 3 && FindType(words[1]) != nullptr) {
        elements.back().min_bytes += static_cast<uint64_t>(FindType(words[1])->bytes);
      } else if (words.size() == 5 && words[1] == "list" && FindType(words[2]) != nullptr &&
                 FindType(words[2])->integer && FindType(words[3]) != nullptr) {
        elements.back().min_bytes += static_cast<uint64_t>(FindType(words[2])->bytes);
      } else {
        return Bad("has a bad property line" + where);
      }
    } else {
      return Bad("has an unknown keyword" + where);
    }
  }

  // An element takes at least its fixed part in binary and two characters per property in text
  // (a digit and a separator), so a count the body cannot hold is a lie that would only cost memory.
  uint64_t body = bytes.size() - pos;
  uint64_t needed = 0;
  for (const auto& element : elements) {
    uint64_t each = binary ? element.min_bytes : 2 * element.properties;
    if (element.count > 0 && each == 0) return Bad("declares an element without properties");
    needed += element.count * each;  // count < 2^32 and each < 2^32: no overflow
    if (needed > body) return Bad("declares more elements than the file holds");
  }
  return Status::Ok();
}

}  // namespace vscan::geometry
