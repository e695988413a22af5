#pragma once
// Numbers in job messages and errors: as printf's %g, or rounded to three significant digits.

#include <cstdio>
#include <string>

namespace vscan::service {

inline std::string Number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", x);
  return buffer;
}

inline std::string Rounded(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", x);
  return buffer;
}

}  // namespace vscan::service
