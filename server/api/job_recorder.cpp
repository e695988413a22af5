#include "api/job_recorder.h"

#include "service/campaign/campaign_summary.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

v1::ScanArtifactInfo ScanInfo(const service::CampaignStepRecord& record) {
  v1::ScanArtifactInfo info;
  info.set_viewpoint_index(record.viewpoint_index);
  info.set_rotation_index(record.rotation_index);
  info.set_table_angle_deg(record.table_angle_deg);
  vscan::ToProto(record.arm.commanded_pose, info.mutable_commanded_sensor_pose());
  vscan::ToProto(record.arm.achieved_pose, info.mutable_sensor_pose());
  const Eigen::VectorXd& c = record.arm.commanded;
  const Eigen::VectorXd& a = record.arm.achieved;
  info.mutable_commanded_joint_positions()->Assign(c.data(), c.data() + c.size());
  info.mutable_achieved_joint_positions()->Assign(a.data(), a.data() + a.size());
  info.set_points(record.points);
  return info;
}

}  // namespace

Status TrackedJobRecorder::Record(const service::JobEventUpdate& update) { return tracker_.Record(job_id_, update); }

StatusOr<std::string> TrackedJobRecorder::RecordArtifact(const std::string& name, const std::string& media_type,
                                                         const std::string& bytes,
                                                         const service::CampaignStepRecord* scan,
                                                         const store::CloudRecord* cloud,
                                                         const service::JobEventUpdate& update) {
  v1::ScanArtifactInfo info;
  if (scan) info = ScanInfo(*scan);
  ASSIGN_OR_RETURN(const v1::Artifact artifact,
                   tracker_.RecordArtifact(job_id_, name, media_type, bytes, scan ? &info : nullptr, update, cloud));
  return artifact.artifact_id();
}

Status TrackedJobRecorder::End(const service::JobEventUpdate& update) { return tracker_.End(job_id_, update); }

}  // namespace vscan::api
