#include "web/web_job_sensor.h"

#include <cstdint>

#include <fmt/format.h>

#include "api/job/job_tracker.h"
#include "api/scan/sensor_request.h"
#include "web/web_json.h"

namespace vscan::web {

WebReply JobSensor(api::JobTracker& tracker, const std::string& job_id) {
  auto job = tracker.Get(job_id);
  if (!job.ok()) return FromStatus(job.status());
  if (!job->has_campaign()) {
    return TextReply(404, fmt::format("job {} is a {} job: only campaigns have a sensor", job_id, job->kind()));
  }
  // The spec was checked against the server's limits when the job started; only its shape matters here.
  service::Limits unbounded;
  unbounded.max_rays_per_scan = UINT64_MAX;
  auto settings = api::SensorFromProto(job->campaign().sensor(), unbounded);
  if (!settings.ok()) return FromStatus(settings.status());
  const sensor::PinholeCamera& camera = settings->camera;
  std::string out = fmt::format("{{\"camera\":{{\"width\":{},\"height\":{}", camera.width, camera.height);
  for (const auto& [name, value] : {std::pair{"fx", camera.fx}, {"fy", camera.fy}, {"cx", camera.cx},
                                    {"cy", camera.cy}, {"near", camera.near}, {"far", camera.far}}) {
    out += fmt::format(",\"{}\":", name);
    AppendJsonNumber(out, value);
  }
  out += "},\"projector\":";
  if (settings->structured_light) {
    const sensor::StructuredLight& light = *settings->structured_light;
    out += "{\"sensor_from_projector\":";
    AppendJsonRows(out, sensor::SensorFromProjector(light).matrix());
    out += ",\"horizontal_fov_deg\":";
    AppendJsonNumber(out, sensor::ProjectorHorizontalFovDeg(light));
    out += ",\"vertical_fov_deg\":";
    AppendJsonNumber(out, sensor::ProjectorVerticalFovDeg(light));
    out += '}';
  } else {
    out += "null";
  }
  return JsonReply(out + "}");
}

}  // namespace vscan::web
