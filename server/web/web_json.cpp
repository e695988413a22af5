#include "web/web_json.h"

#include <cmath>

#include <fmt/format.h>

#include "vscan/common/json_quote.h"

namespace vscan::web {

void AppendJsonNumber(std::string& out, double value) {
  out += std::isfinite(value) ? fmt::format("{}", value) : "null";
}

void AppendJsonString(std::string& out, std::string_view text) { out += JsonQuote(text); }

void AppendJsonVector(std::string& out, const Eigen::Vector3d& v) {
  out += '[';
  for (int k = 0; k < 3; ++k) {
    if (k) out += ',';
    AppendJsonNumber(out, v[k]);
  }
  out += ']';
}

void AppendJsonRows(std::string& out, const Eigen::Matrix4d& m) {
  out += '[';
  for (int r = 0; r < 4; ++r) {
    out += r ? ",[" : "[";
    for (int c = 0; c < 4; ++c) {
      if (c) out += ',';
      AppendJsonNumber(out, m(r, c));
    }
    out += ']';
  }
  out += ']';
}

}  // namespace vscan::web
