#pragma once
// A small synchronous C++ client for vscand. Every call returns a Status naming what went wrong;
// errors from the server keep their gRPC code (see vscan/common/grpc_status.h).

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>

#include "grpc/health/v1/health.grpc.pb.h"
#include "vscan/client/types.h"
#include "vscan/common/status.h"
#include "vscan/v1/cloud.grpc.pb.h"
#include "vscan/v1/job.grpc.pb.h"
#include "vscan/v1/robot.grpc.pb.h"
#include "vscan/v1/scan.grpc.pb.h"
#include "vscan/v1/scene.grpc.pb.h"

namespace vscan::client {

class Client {
 public:
  // Opens a channel to target ("host:port", "unix:/path", ...). Fails only on bad options,
  // e.g. an unreadable root certificate; the server is first contacted by the first call.
  static StatusOr<Client> Connect(const std::string& target, const ClientOptions& options = {});
  // Uses an existing channel (in-process servers, custom credentials).
  explicit Client(std::shared_ptr<grpc::Channel> channel, ClientOptions options = {});

  Client(Client&&) noexcept;
  Client& operator=(Client&&) noexcept;
  ~Client();

  const ClientOptions& options() const { return options_; }
  const std::shared_ptr<grpc::Channel>& channel() const { return channel_; }
  // Applies a deadline (if timeout is positive) and the bearer token to a fresh call.
  void PrepareContext(grpc::ClientContext* context, std::chrono::milliseconds timeout) const;

  // grpc.health.v1 Check; service "" asks about the server as a whole.
  StatusOr<grpc::health::v1::HealthCheckResponse> Health(const std::string& service = "");

  StatusOr<v1::Scene> CreateScene(const std::string& name);
  StatusOr<v1::Scene> GetScene(const std::string& scene_id);
  // Every scene, following page tokens.
  StatusOr<std::vector<v1::Scene>> ListScenes();
  Status DeleteScene(const std::string& scene_id);

  // Streams the file in options.chunk_bytes pieces after a header that carries its size.
  StatusOr<v1::Mesh> UploadMeshFile(const std::string& path, MeshUploadOptions options,
                                    const ProgressFn& progress = {});
  // Same, from bytes in memory; options.format is required.
  StatusOr<v1::Mesh> UploadMeshBytes(std::string_view bytes, const MeshUploadOptions& options,
                                     const ProgressFn& progress = {});
  StatusOr<v1::Mesh> GetMesh(const std::string& mesh_id);
  // Every mesh, following page tokens.
  StatusOr<std::vector<v1::Mesh>> ListMeshes();
  Status DeleteMesh(const std::string& mesh_id);

  StatusOr<v1::AddObjectResponse> AddObject(const std::string& scene_id, const std::string& mesh_id,
                                            const ObjectPlacement& placement);
  // pose unset keeps the current pose; scale 0 keeps the current scale.
  StatusOr<v1::MoveObjectResponse> MoveObject(const std::string& scene_id, const std::string& object_id,
                                              const std::optional<v1::Pose>& pose, double scale = 0.0);
  // Sets an object's material override; nullopt clears it (the object takes its mesh's again).
  StatusOr<v1::SetObjectMaterialResponse> SetObjectMaterial(const std::string& scene_id, const std::string& object_id,
                                                            const std::optional<v1::Material>& material);
  // The named materials the server knows, with their values.
  StatusOr<std::vector<v1::MaterialPreset>> ListMaterialPresets();
  // Returns the scene's new revision.
  StatusOr<uint64_t> RemoveObject(const std::string& scene_id, const std::string& object_id);
  StatusOr<v1::SetRotaryTableResponse> SetRotaryTable(const std::string& scene_id, const v1::RotaryTable& table);

  // Runs a scan and assembles its chunks; checks that the point count matches the header.
  StatusOr<ScanResult> Scan(const v1::ScanRequest& request, const ScanCallbacks& callbacks = {});
  StatusOr<std::vector<v1::SensorPreset>> ListSensorPresets();

  // Robots. Streams the files after a header; big files travel in options.chunk_bytes pieces.
  StatusOr<v1::Robot> UploadRobot(const RobotUploadOptions& options, const std::vector<RobotFile>& files,
                                  const ProgressFn& progress = {});
  // A directory (every regular file below it, paths relative to it) or a single URDF file.
  StatusOr<v1::Robot> UploadRobotPath(const std::string& path, RobotUploadOptions options,
                                      const ProgressFn& progress = {});
  StatusOr<v1::Robot> GetRobot(const std::string& robot_id);
  // Every robot, following page tokens.
  StatusOr<std::vector<v1::Robot>> ListRobots();
  Status DeleteRobot(const std::string& robot_id);
  StatusOr<v1::ForwardKinematicsResponse> ForwardKinematics(const v1::ForwardKinematicsRequest& request);
  // OUT_OF_RANGE for an unreachable goal unless request.allow_partial is set.
  StatusOr<v1::InverseKinematicsResponse> InverseKinematics(const v1::InverseKinematicsRequest& request);
  StatusOr<v1::MountRobotResponse> MountRobot(const v1::MountRobotRequest& request);
  StatusOr<v1::Mount> GetMount(const std::string& mount_id);
  // Every mount of a scene (every scene's when scene_id is empty), following page tokens.
  StatusOr<std::vector<v1::Mount>> ListMounts(const std::string& scene_id = "");
  // Returns the scene's new revision.
  StatusOr<uint64_t> UnmountRobot(const std::string& mount_id);

  // Jobs: scan campaigns, model jobs and their artifacts.
  StatusOr<v1::Job> StartCampaign(const v1::CampaignSpec& spec);
  // StartCampaign with validate_only: the server's verdict on spec; nothing is started. Empty
  // scene_id and mount_id are not looked up.
  Status ValidateCampaign(const v1::CampaignSpec& spec);
  // A model job: aligns stored clouds (a list, or a campaign's scans), and reconstructs and
  // evaluates them when spec asks.
  StatusOr<v1::Job> StartModel(const v1::ModelSpec& spec);
  // StartModel with validate_only: the server's verdict on spec; nothing is started.
  Status ValidateModel(const v1::ModelSpec& spec);
  // A bin fill: parts dropped into an open bin, then placed in the scene where they settled.
  StatusOr<v1::Job> StartBinFill(const v1::BinFillSpec& spec);
  // StartBinFill with validate_only: an empty scene_id is not looked up; mesh ids are.
  Status ValidateBinFill(const v1::BinFillSpec& spec);
  // A picking job: a mounted robot empties the bin a succeeded bin fill left in its scene.
  StatusOr<v1::Job> StartPicking(const v1::PickingSpec& spec);
  // StartPicking with validate_only: the server's verdict on spec; nothing is started.
  Status ValidatePicking(const v1::PickingSpec& spec);
  // Sends a client-perception picking job the estimates of the step it awaits; how many it stored.
  StatusOr<uint32_t> SubmitPickingEstimates(const v1::SubmitPickingEstimatesRequest& request);
  StatusOr<v1::Job> GetJob(const std::string& job_id);
  // Every job, following page tokens.
  StatusOr<std::vector<v1::Job>> ListJobs();
  StatusOr<v1::Job> CancelJob(const std::string& job_id);
  // Runs an ended campaign (INTERRUPTED, CANCELLED, FAILED) again as the same job: its stored scans
  // are kept and only the missing steps captured. Returns the job queued again.
  StatusOr<v1::Job> ResumeJob(const std::string& job_id);
  // Deletes an ended job and its artifacts (FAILED_PRECONDITION while it runs: cancel it first).
  StatusOr<v1::DeleteJobResponse> DeleteJob(const std::string& job_id);
  // Calls on_event for each message until the server ends the stream (the job finished) or
  // on_event returns false.
  Status WatchJob(const std::string& job_id, const JobEventFn& on_event);
  // Passes the artifact's bytes to sink in order; checks the count against its metadata.
  StatusOr<v1::Artifact> ReadArtifact(const std::string& job_id, const std::string& artifact_id,
                                      const ArtifactSink& sink, const ProgressFn& progress = {});

  // Stored clouds: uploads (PLY or PCD, streamed after a header that carries the size), the
  // campaigns' scans, reads as binary PLY.
  StatusOr<v1::Cloud> UploadCloudFile(const std::string& path, CloudUploadOptions options,
                                      const ProgressFn& progress = {});
  StatusOr<v1::Cloud> UploadCloudBytes(std::string_view bytes, const CloudUploadOptions& options,
                                       const ProgressFn& progress = {});
  StatusOr<v1::Cloud> GetCloud(const std::string& cloud_id);
  // Every cloud (only job_id's scans when it is set), following page tokens.
  StatusOr<std::vector<v1::Cloud>> ListClouds(const std::string& job_id = "");
  // Deletes an uploaded cloud (FAILED_PRECONDITION for a campaign's scan: it goes with its job).
  StatusOr<v1::DeleteCloudResponse> DeleteCloud(const std::string& cloud_id);
  // Passes the cloud's binary PLY to sink in order; checks the count against its metadata.
  StatusOr<v1::Cloud> ReadCloud(const std::string& cloud_id, const ArtifactSink& sink,
                                const ProgressFn& progress = {});

 private:
  StatusOr<v1::Mesh> Upload(const MeshUploadOptions& options, uint64_t size,
                            const std::function<StatusOr<size_t>(char*, size_t)>& read,
                            const ProgressFn& progress);

  ClientOptions options_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::SceneService::Stub> scenes_;
  std::unique_ptr<v1::ScanService::Stub> scans_;
  std::unique_ptr<grpc::health::v1::Health::Stub> health_;
};

}  // namespace vscan::client
