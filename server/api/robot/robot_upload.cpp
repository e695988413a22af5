// RobotService.UploadRobot: collects the bundle from the client stream, then imports it on a
// worker thread.

#include <string>

#include <spdlog/spdlog.h>

#include "api/robot/robot_convert.h"
#include "api/robot/robot_service.h"
#include "api/transport/upload_reactor.h"
#include "api/transport/validate.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr size_t kMaxPathBytes = 4096;

std::string FileField(size_t i) { return "files[" + std::to_string(i) + "].path"; }

class UploadRobotReactor final : public UploadReactor<v1::UploadRobotRequest> {
 public:
  UploadRobotReactor(grpc::CallbackServerContext* ctx, v1::UploadRobotResponse* response, service::ServiceContext& context)
      : UploadReactor(ctx, context, "UploadRobot"), response_(response) {
    Start();
  }

 private:
  uint64_t limit() const { return context_.robots.max_bundle_bytes(); }

  Status Accept(const v1::UploadRobotRequest& request) override {
    switch (request.part_case()) {
      case v1::UploadRobotRequest::kHeader: return AcceptHeader(request.header());
      case v1::UploadRobotRequest::kFile: return AcceptFile(request.file());
      case v1::UploadRobotRequest::PART_NOT_SET: break;
    }
    return InvalidArgument("part: every message carries a header or a file");
  }

  Status AcceptHeader(const v1::RobotBundleHeader& header) {
    if (has_header_) return InvalidArgument("header: sent twice; only the first message is a header");
    has_header_ = true;
    RETURN_IF_ERROR(CheckText(header.name(), "header.name"));
    RETURN_IF_ERROR(CheckText(header.urdf_path(), "header.urdf_path", kMaxPathBytes));
    RETURN_IF_ERROR(CheckText(header.base_link(), "header.base_link"));
    RETURN_IF_ERROR(CheckText(header.tip_link(), "header.tip_link"));
    if (header.urdf_path().empty())
      return InvalidArgument("header.urdf_path: required (the URDF's path in the bundle)");
    if (header.size_bytes() > limit()) {
      return ResourceExhausted("header.size_bytes: " + std::to_string(header.size_bytes()) +
                               " bytes exceeds the robot bundle limit of " + std::to_string(limit()) +
                               " (--max-robot-bundle-mib)");
    }
    upload_.name = header.name();
    upload_.urdf_path = header.urdf_path();
    upload_.base_link = header.base_link();
    upload_.tip_link = header.tip_link();
    if (header.has_tool_offset()) {
      ASSIGN_OR_RETURN(upload_.tip_from_tool, PoseFromProto(header.tool_offset(), "header.tool_offset"));
    }
    return Status::Ok();
  }

  Status AcceptFile(const v1::RobotBundleFile& file) {
    if (!has_header_) return InvalidArgument("header: the first message must carry the header");
    const bool starts = !file.path().empty();
    if (!starts && upload_.files.empty()) {
      return InvalidArgument(FileField(0) + ": required (a file's first message names it)");
    }
    const size_t index = starts ? upload_.files.size() : upload_.files.size() - 1;
    if (starts && upload_.files.size() >= context_.robots.max_files()) {
      return ResourceExhausted(FileField(index) + ": more than " + std::to_string(context_.robots.max_files()) +
                               " files in one bundle (--max-robot-files)");
    }
    RETURN_IF_ERROR(CheckText(file.path(), FileField(index), kMaxPathBytes));
    total_bytes_ += file.path().size() + file.content().size();
    if (total_bytes_ > limit()) {
      return ResourceExhausted(FileField(index) + ": the bundle exceeds the robot bundle limit of " +
                               std::to_string(limit()) + " bytes (--max-robot-bundle-mib)");
    }
    if (starts) upload_.files.push_back({file.path(), std::string()});
    upload_.files.back().bytes += file.content();
    return Status::Ok();
  }

  Status Complete() override {
    if (!has_header_) return InvalidArgument("header: the first message must carry the header");
    ASSIGN_OR_RETURN(auto robot, context_.robots.AddRobot(std::move(upload_)));
    spdlog::info("robot {} '{}' uploaded: {} joints, {} files, {} warnings", robot.robot_id, robot.name,
                 robot.joints.size(), robot.file_count, robot.warnings.size());
    ToProto(robot, response_->mutable_robot());
    return Status::Ok();
  }

  v1::UploadRobotResponse* response_;
  bool has_header_ = false;
  robot_registry::RobotUpload upload_;
  uint64_t total_bytes_ = 0;
};

}  // namespace

grpc::ServerReadReactor<v1::UploadRobotRequest>* RobotService::UploadRobot(grpc::CallbackServerContext* ctx,
                                                                           v1::UploadRobotResponse* response) {
  return new UploadRobotReactor(ctx, response, context_);
}

}  // namespace vscan::api
