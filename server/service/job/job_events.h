#pragma once
// What a running job reports, and to whom: every change is recorded durably before anyone sees it.

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "service/job/report_writer.h"
#include "store/cloud_catalogue.h"
#include "store/job_catalogue.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::service {

// A scan stored as a job's artifact, described so that a resumed run can pass over its step and a
// client can tell where it was taken.
struct ScanArtifact {
  uint32_t rotation_index = 0;
  uint32_t viewpoint_index = 0;
  double table_angle_deg = 0;
  Pose3 commanded_sensor_pose = Pose3::Identity();
  Pose3 sensor_pose = Pose3::Identity();  // where the arm reached
  Eigen::VectorXd commanded_joint_positions;
  Eigen::VectorXd achieved_joint_positions;
  uint64_t points = 0;
};

// One scan's alignment as a model job reports it (a model job's events, model.json).
struct ScanAlignmentRecord {
  std::string cloud_id;
  std::string name;
  uint32_t index = 0;  // in the job's list of clouds
  bool aligned = false;
  std::string reason;  // why not aligned
  Pose3 model_from_sensor = Pose3::Identity();
  double fitness = 0;
  double inlier_rmse = 0;
  // Points in the union (one per alignment voxel) once this scan was merged: the union growing.
  uint64_t union_points = 0;
  // Against the true pose, when the server knows it.
  bool has_error = false;
  double rotation_error_deg = 0;
  double translation_error_m = 0;
  double initial_rotation_error_deg = 0;
  double initial_translation_error_m = 0;
};

// What one event changes.
struct JobEventUpdate {
  store::JobState state = store::JobState::kRunning;
  std::string message;
  uint32_t steps_done = 0;
  uint32_t step = 0;
  bool pose_reached = false;
  // Set when a scan was aligned (or found unalignable).
  std::optional<ScanAlignmentRecord> alignment;
};

// Where a job's events and artifacts go (the job tracker, in vscand).
class JobRecorder {
 public:
  virtual ~JobRecorder() = default;
  virtual Status Record(const JobEventUpdate& update) = 0;
  // Stores bytes durably and records them with the event; scan, when given, describes the scan
  // the bytes hold, and cloud the stored cloud they also are (its origin, job, blob and size are
  // filled in). Returns the artifact's id.
  virtual StatusOr<std::string> RecordArtifact(const std::string& name, const std::string& media_type,
                                               const std::string& bytes, const ScanArtifact* scan,
                                               const store::CloudRecord* cloud, const JobEventUpdate& update) = 0;
  // The final event: update.state must be final.
  virtual Status End(const JobEventUpdate& update) = 0;
  // How the job's JSON reports are printed before RecordArtifact stores them.
  virtual const ReportWriter& reports() const = 0;
};

}  // namespace vscan::service
