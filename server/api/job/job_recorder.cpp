#include "api/job/job_recorder.h"

#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

v1::ScanArtifactInfo ScanInfo(const service::ScanArtifact& scan) {
  v1::ScanArtifactInfo info;
  info.set_viewpoint_index(scan.viewpoint_index);
  info.set_rotation_index(scan.rotation_index);
  info.set_table_angle_deg(scan.table_angle_deg);
  vscan::ToProto(scan.commanded_sensor_pose, info.mutable_commanded_sensor_pose());
  vscan::ToProto(scan.sensor_pose, info.mutable_sensor_pose());
  const Eigen::VectorXd& c = scan.commanded_joint_positions;
  const Eigen::VectorXd& a = scan.achieved_joint_positions;
  info.mutable_commanded_joint_positions()->Assign(c.data(), c.data() + c.size());
  info.mutable_achieved_joint_positions()->Assign(a.data(), a.data() + a.size());
  info.set_points(scan.points);
  return info;
}

}  // namespace

Status TrackedJobRecorder::Record(const service::JobEventUpdate& update) { return tracker_.Record(job_id_, update); }

StatusOr<std::string> TrackedJobRecorder::RecordArtifact(const std::string& name, const std::string& media_type,
                                                         const std::string& bytes,
                                                         const service::ScanArtifact* scan,
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
