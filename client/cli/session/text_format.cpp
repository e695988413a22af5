#include "session/text_format.h"

#include <cctype>
#include <cstdio>
#include <filesystem>

namespace vscan::cli {

std::string Fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string LowerExtension(const std::string& path) { return Lower(std::filesystem::path(path).extension().string()); }

}  // namespace vscan::cli
