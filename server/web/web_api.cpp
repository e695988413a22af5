#include "web/web_api.h"

#include <cctype>

#include <fmt/format.h>

#include "web/web_bins.h"
#include "web/web_clouds.h"
#include "web/web_datasets.h"
#include "web/web_jobs.h"
#include "web/web_robots.h"
#include "web/web_scenes.h"

namespace vscan::web {
namespace {

// Compares every byte whatever the first difference, so that timing does not reveal the token.
bool SameToken(std::string_view sent, std::string_view token) {
  if (sent.size() != token.size()) return false;
  unsigned char difference = 0;
  for (size_t i = 0; i < token.size(); ++i) difference |= static_cast<unsigned char>(sent[i] ^ token[i]);
  return difference == 0;
}

bool Authorized(std::string_view authorization, const std::string& token) {
  if (token.empty()) return true;
  constexpr std::string_view kBearer = "Bearer ";
  if (authorization.size() < kBearer.size()) return false;
  for (size_t i = 0; i < kBearer.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(authorization[i])) !=
        std::tolower(static_cast<unsigned char>(kBearer[i]))) {
      return false;
    }
  }
  return SameToken(authorization.substr(kBearer.size()), token);
}

std::vector<std::string_view> Split(std::string_view path) {
  std::vector<std::string_view> segments;
  while (true) {
    const size_t slash = path.find('/');
    segments.push_back(path.substr(0, slash));
    if (slash == std::string_view::npos) return segments;
    path = path.substr(slash + 1);
  }
}

}  // namespace

WebApi::WebApi(WebSources sources, WebApiOptions options)
    : sources_(sources), options_(std::move(options)), streams_(std::make_shared<JobStreams>()) {}

void WebApi::StopStreams() { streams_->Stop(); }

WebReply WebApi::Handle(std::string_view method, std::string_view path, std::string_view query,
                        std::string_view authorization) const {
  if (method != "GET") return TextReply(405, "the web view is read-only: only GET is served");
  if (!Authorized(authorization, options_.token)) {
    return TextReply(401, "authorization: missing or wrong bearer token");
  }
  constexpr std::string_view kApi = "/api/";
  if (!path.starts_with(kApi)) return TextReply(404, fmt::format("no such resource: {}", path));
  const WebRequest request{method, Split(path.substr(kApi.size())), query};
  const std::string_view noun = request.segments[0];
  if (noun == "scenes" || noun == "meshes") return ServeScenes(sources_, options_, request);
  if (noun == "mounts") return ServeMounts(sources_, request);
  if (noun == "datasets") return ServeDatasets(sources_, options_, request);
  if (noun == "jobs") return ServeJobs(sources_, streams_, request);
  if (noun == "clouds") return ServeClouds(sources_, request);
  if (noun == "bins") return ServeBins(sources_, request);
  return TextReply(404, fmt::format("no such resource: {}", path));
}

}  // namespace vscan::web
