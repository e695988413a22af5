#pragma once
// A whole file's bytes (empty when it cannot be read).

#include <fstream>
#include <sstream>
#include <string>

namespace vscan::test {

inline std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace vscan::test
