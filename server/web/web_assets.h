#pragma once
// The page's files (web/ in the source tree), compiled into vscand.

#include <string_view>

namespace vscan::web {

struct WebAsset {
  std::string_view path;  // as requested, e.g. "/app.js"
  std::string_view content_type;
  std::string_view body;
};

// The asset served at path, or null.
const WebAsset* FindAsset(std::string_view path);

}  // namespace vscan::web
