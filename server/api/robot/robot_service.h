#pragma once
// RobotService: robot bundles, kinematics, and mounts of robots in scenes.

#include "service/context/service_context.h"
#include "vscan/v1/robot.grpc.pb.h"

namespace vscan::api {

class RobotService final : public v1::RobotService::CallbackService {
 public:
  explicit RobotService(service::ServiceContext& context) : context_(context) {}

  grpc::ServerReadReactor<v1::UploadRobotRequest>* UploadRobot(grpc::CallbackServerContext* ctx,
                                                               v1::UploadRobotResponse* response) override;
  grpc::ServerUnaryReactor* GetRobot(grpc::CallbackServerContext* ctx, const v1::GetRobotRequest* request,
                                     v1::GetRobotResponse* response) override;
  grpc::ServerUnaryReactor* ListRobots(grpc::CallbackServerContext* ctx, const v1::ListRobotsRequest* request,
                                       v1::ListRobotsResponse* response) override;
  grpc::ServerUnaryReactor* DeleteRobot(grpc::CallbackServerContext* ctx, const v1::DeleteRobotRequest* request,
                                        v1::DeleteRobotResponse* response) override;
  grpc::ServerUnaryReactor* ForwardKinematics(grpc::CallbackServerContext* ctx,
                                              const v1::ForwardKinematicsRequest* request,
                                              v1::ForwardKinematicsResponse* response) override;
  grpc::ServerUnaryReactor* InverseKinematics(grpc::CallbackServerContext* ctx,
                                              const v1::InverseKinematicsRequest* request,
                                              v1::InverseKinematicsResponse* response) override;
  grpc::ServerUnaryReactor* MountRobot(grpc::CallbackServerContext* ctx, const v1::MountRobotRequest* request,
                                       v1::MountRobotResponse* response) override;
  grpc::ServerUnaryReactor* GetMount(grpc::CallbackServerContext* ctx, const v1::GetMountRequest* request,
                                     v1::GetMountResponse* response) override;
  grpc::ServerUnaryReactor* ListMounts(grpc::CallbackServerContext* ctx, const v1::ListMountsRequest* request,
                                       v1::ListMountsResponse* response) override;
  grpc::ServerUnaryReactor* UnmountRobot(grpc::CallbackServerContext* ctx, const v1::UnmountRobotRequest* request,
                                         v1::UnmountRobotResponse* response) override;

 private:
  service::ServiceContext& context_;
};

}  // namespace vscan::api
