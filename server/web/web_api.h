#pragma once
// The web view's read-only API, apart from HTTP: a request's method, path and authorization
// header in, a status, content type and body out. Reads the scene registry the gRPC services use.

#include <cstdint>
#include <string>
#include <string_view>

namespace vscan::scenes {
class SceneRegistry;
}

namespace vscan::web {

struct WebReply {
  int status = 200;
  std::string content_type;
  std::string body;
};

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
  // The registry must outlive the API.
  WebApi(scenes::SceneRegistry& registry, WebApiOptions options);
  // path: the request path without its query string, starting with "/api/".
  WebReply Handle(std::string_view method, std::string_view path, std::string_view authorization) const;

 private:
  WebReply Scenes() const;
  WebReply Scene(const std::string& scene_id) const;
  WebReply Mesh(const std::string& mesh_id) const;

  scenes::SceneRegistry& registry_;
  WebApiOptions options_;
};

}  // namespace vscan::web
