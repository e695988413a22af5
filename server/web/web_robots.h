#pragma once
// /api/mounts: a scene's mounted robot drawn in a pose: its links' meshes placed in the world and
// where the sensor on its flange stands.

#include "web/web_request.h"
#include "web/web_sources.h"

namespace vscan::web {

// GET /api/mounts/{id}[?joints=q1,q2,...]: JSON (web_encode.h MountJson); the joints default to the
// home pose the services use. GET /api/mounts/{id}/shapes/{k}: shape k's mesh in its own frame.
WebReply ServeMounts(const WebSources& sources, const WebRequest& request);

}  // namespace vscan::web
