#pragma once
// /api/scenes and /api/meshes: the scene registry's scenes as JSON, meshes as binary (web_encode.h).

#include "web/web_request.h"
#include "web/web_sources.h"

namespace vscan::web {

struct WebApiOptions;

// segments[0] is "scenes" or "meshes".
WebReply ServeScenes(const WebSources& sources, const WebApiOptions& options, const WebRequest& request);

}  // namespace vscan::web
