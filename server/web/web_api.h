#pragma once
// The web view's read-only API, apart from HTTP: a request's method, path, query and authorization
// header in, a reply out. Checks the token, then hands the request to the handler of its noun
// (web_scenes.h, ...), each reading the stores the gRPC services use (web_sources.h).

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "web/web_request.h"
#include "web/web_sources.h"

namespace vscan::web {

class JobStreams;

struct WebApiOptions {
  // Requests must send "Authorization: Bearer <token>" when set (the gRPC token).
  std::string token;
  // Meshes with more triangles are refused (422) rather than sent to a browser.
  uint64_t max_mesh_triangles = 4'000'000;
  // Scenes listed by /api/scenes.
  int max_scenes = 1000;
};

class WebApi {
 public:
  // The sources must outlive the API.
  WebApi(WebSources sources, WebApiOptions options);
  // path: the request path without its query string, starting with "/api/"; query: what followed
  // '?', if anything.
  WebReply Handle(std::string_view method, std::string_view path, std::string_view query,
                  std::string_view authorization) const;
  // Ends the open event streams and refuses new ones (the view is stopping).
  void StopStreams();

 private:
  WebSources sources_;
  WebApiOptions options_;
  std::shared_ptr<JobStreams> streams_;
};

}  // namespace vscan::web
