#pragma once
// GET /api/jobs/{id}/sensor: a campaign's sensor as the page draws it, its preset (if any) resolved
// by the same code scans use: {"camera": {"width","height","fx","fy","cx","cy","near","far"},
// "projector": null | {"sensor_from_projector": 4 rows of 4, "horizontal_fov_deg", "vertical_fov_deg"}}.

#include <string>

#include "web/web_request.h"

namespace vscan::api {
class JobTracker;
}

namespace vscan::web {

WebReply JobSensor(api::JobTracker& tracker, const std::string& job_id);

}  // namespace vscan::web
