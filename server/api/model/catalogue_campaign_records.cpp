#include "api/model/catalogue_campaign_records.h"

#include "api/scan/returned_light_request.h"
#include "api/scan/sensor_request.h"
#include "vscan/common/proto_convert.h"
#include "vscan/v1/job.pb.h"
#include "service/job/job_kind.h"

namespace vscan::api {

StatusOr<service::CampaignRecord> CatalogueCampaignRecords::Get(const std::string& job_id) {
  ASSIGN_OR_RETURN(const store::JobRecord job, catalogue_.GetJob(job_id));
  service::CampaignRecord record;
  record.job_id = job.job_id;
  record.kind = job.kind;
  record.state = job.state;
  if (job.kind != service::JobKindName(service::JobKind::kCampaign)) return record;
  v1::CampaignSpec spec;
  if (!spec.ParseFromString(job.spec)) {
    return DataLoss("job catalogue: job '" + job.job_id + "' has an unreadable campaign spec");
  }
  record.scene_id = spec.scene_id();
  record.mount_id = spec.mount_id();
  record.encoder_noise = spec.apply_encoder_noise();
  if (spec.has_returned_light()) {
    // Checked when the campaign started; a spec that no longer reads only loses the light's effect.
    auto sensor = SensorFromProto(spec.sensor(), limits_);
    if (sensor.ok()) {
      auto light = ReturnedLightFromProto(spec.returned_light(), sensor->camera, sensor->structured_light,
                                          sensor->modulation_frequency_hz, sensor->illumination);
      if (light.ok()) record.returned_light = std::move(light).value();
    }
  }
  for (const store::ArtifactRecord& artifact : job.artifacts) {
    if (artifact.info.empty()) continue;
    v1::ScanArtifactInfo info;
    if (!info.ParseFromString(artifact.info)) {
      return DataLoss("job catalogue: artifact '" + artifact.artifact_id + "' has an unreadable description");
    }
    service::CampaignScanRecord scan;
    scan.name = artifact.name;
    if (info.has_commanded_sensor_pose()) {
      auto pose = PoseFromProto(info.commanded_sensor_pose(), "commanded_sensor_pose");
      if (pose.ok()) scan.commanded_world_from_sensor = *pose;
    }
    const auto& joints = info.commanded_joint_positions();
    scan.commanded_joints = Eigen::Map<const Eigen::VectorXd>(joints.data(), joints.size());
    record.scans.push_back(std::move(scan));
  }
  return record;
}

}  // namespace vscan::api
