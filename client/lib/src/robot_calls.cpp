#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "paging.h"
#include "unary_call.h"

namespace vscan::client {
namespace {

using RobotStub = v1::RobotService::Stub;

std::unique_ptr<RobotStub> NewRobotStub(const Client& client) { return v1::RobotService::NewStub(client.channel()); }

StatusOr<std::string> ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path.string() + ": cannot open");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) return DataLoss(path.string() + ": read failed");
  return bytes.str();
}

bool IsUrdf(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".urdf";
}

// True when path, already made absolute and free of links, lies inside root (or is root).
bool IsWithin(const std::filesystem::path& path, const std::filesystem::path& root) {
  const std::filesystem::path relative = path.lexically_relative(root);
  return !relative.empty() && *relative.begin() != "..";
}

// A symbolic link may point anywhere; one that resolves outside the bundle is refused, so that
// an upload never carries files from elsewhere on this machine.
Status CheckLink(const std::filesystem::directory_entry& entry, const std::filesystem::path& root) {
  std::error_code ec;
  const std::filesystem::path target = std::filesystem::weakly_canonical(entry.path(), ec);
  if (ec) return NotFound(entry.path().string() + ": cannot resolve the symbolic link: " + ec.message());
  if (IsWithin(target, root)) return Status::Ok();
  return InvalidArgument(entry.path().string() + ": symbolic link to '" + target.string() +
                         "' leaves the bundle directory");
}

// Every regular file below dir, with its path relative to dir, in path order. Directory links
// are not descended into; file links are followed when they stay inside dir.
StatusOr<std::vector<RobotFile>> ReadDirectory(const std::filesystem::path& dir) {
  std::vector<RobotFile> files;
  std::error_code ec;
  const std::filesystem::path root = std::filesystem::canonical(dir, ec);
  if (ec) return NotFound(dir.string() + ": " + ec.message());
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code entry_ec;  // an entry that cannot be inspected (a dangling link) is skipped
    if (it->is_symlink(entry_ec)) RETURN_IF_ERROR(CheckLink(*it, root));
    if (!it->is_regular_file(entry_ec)) continue;
    ASSIGN_OR_RETURN(std::string bytes, ReadFile(it->path()));
    files.push_back({it->path().lexically_relative(dir).generic_string(), std::move(bytes)});
  }
  if (ec) return NotFound(dir.string() + ": " + ec.message());
  std::sort(files.begin(), files.end(), [](const RobotFile& a, const RobotFile& b) { return a.path < b.path; });
  return files;
}

StatusOr<std::string> FindUrdf(const std::filesystem::path& dir, const std::vector<RobotFile>& files) {
  std::vector<std::string> urdfs;
  for (const RobotFile& file : files) {
    if (IsUrdf(file.path)) urdfs.push_back(file.path);
  }
  if (urdfs.size() == 1) return urdfs.front();
  return InvalidArgument("urdf_path", "required, " + dir.string() + " holds " + std::to_string(urdfs.size()) +
                         " .urdf files");
}

}  // namespace

StatusOr<v1::Robot> Client::UploadRobot(const RobotUploadOptions& options, const std::vector<RobotFile>& files,
                                        const ProgressFn& progress) {
  uint64_t total = 0;
  for (const RobotFile& file : files) total += file.bytes.size();
  auto stub = NewRobotStub(*this);
  grpc::ClientContext context;
  PrepareContext(&context, options_.stream_timeout);
  v1::UploadRobotResponse response;
  auto writer = stub->UploadRobot(&context, &response);

  v1::UploadRobotRequest message;
  v1::RobotBundleHeader* header = message.mutable_header();
  header->set_name(options.name);
  header->set_urdf_path(options.urdf_path);
  header->set_base_link(options.base_link);
  header->set_tip_link(options.tip_link);
  if (options.tool_offset) *header->mutable_tool_offset() = *options.tool_offset;
  header->set_size_bytes(total);
  bool open = writer->Write(message);

  const size_t piece = std::max<size_t>(options.chunk_bytes, 1);
  uint64_t sent = 0;
  for (const RobotFile& file : files) {
    size_t offset = 0;
    do {
      const size_t take = std::min(piece, file.bytes.size() - offset);
      message.Clear();
      v1::RobotBundleFile* part = message.mutable_file();
      if (offset == 0) part->set_path(file.path);
      part->set_content(file.bytes.data() + offset, take);
      open = open && writer->Write(message);
      offset += take;
      sent += take;
      if (open && progress) progress(sent, total);
    } while (open && offset < file.bytes.size());
    if (!open) break;
  }
  if (open) writer->WritesDone();
  const grpc::Status status = writer->Finish();
  if (!status.ok()) return FromGrpc(status);
  return std::move(*response.mutable_robot());
}

StatusOr<v1::Robot> Client::UploadRobotPath(const std::string& path, RobotUploadOptions options,
                                            const ProgressFn& progress) {
  std::error_code ec;
  const std::filesystem::path root(path);
  if (std::filesystem::is_directory(root, ec)) {
    ASSIGN_OR_RETURN(const std::vector<RobotFile> files, ReadDirectory(root));
    if (options.urdf_path.empty()) {
      ASSIGN_OR_RETURN(options.urdf_path, FindUrdf(root, files));
    }
    return UploadRobot(options, files, progress);
  }
  ASSIGN_OR_RETURN(std::string bytes, ReadFile(root));
  const std::string name = root.filename().string();
  if (options.urdf_path.empty()) options.urdf_path = name;
  return UploadRobot(options, {RobotFile{name, std::move(bytes)}}, progress);
}

StatusOr<v1::Robot> Client::GetRobot(const std::string& robot_id) {
  v1::GetRobotRequest request;
  request.set_robot_id(robot_id);
  auto stub = NewRobotStub(*this);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &RobotStub::GetRobot, request));
  return std::move(*response.mutable_robot());
}

StatusOr<std::vector<v1::Robot>> Client::ListRobots() {
  auto stub = NewRobotStub(*this);
  return CollectPages<v1::Robot>(
      [this, &stub](const std::string& token) {
        v1::ListRobotsRequest request;
        request.set_page_token(token);
        return UnaryCall(*this, *stub, &RobotStub::ListRobots, request);
      },
      [](const v1::ListRobotsResponse& page) -> const auto& { return page.robots(); });
}

Status Client::DeleteRobot(const std::string& robot_id) {
  v1::DeleteRobotRequest request;
  request.set_robot_id(robot_id);
  auto stub = NewRobotStub(*this);
  return UnaryCall(*this, *stub, &RobotStub::DeleteRobot, request).status();
}

StatusOr<v1::ForwardKinematicsResponse> Client::ForwardKinematics(const v1::ForwardKinematicsRequest& request) {
  auto stub = NewRobotStub(*this);
  return UnaryCall(*this, *stub, &RobotStub::ForwardKinematics, request);
}

StatusOr<v1::InverseKinematicsResponse> Client::InverseKinematics(const v1::InverseKinematicsRequest& request) {
  auto stub = NewRobotStub(*this);
  return UnaryCall(*this, *stub, &RobotStub::InverseKinematics, request);
}

StatusOr<v1::MountRobotResponse> Client::MountRobot(const v1::MountRobotRequest& request) {
  auto stub = NewRobotStub(*this);
  return UnaryCall(*this, *stub, &RobotStub::MountRobot, request);
}

StatusOr<v1::Mount> Client::GetMount(const std::string& mount_id) {
  v1::GetMountRequest request;
  request.set_mount_id(mount_id);
  auto stub = NewRobotStub(*this);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &RobotStub::GetMount, request));
  return std::move(*response.mutable_mount());
}

StatusOr<std::vector<v1::Mount>> Client::ListMounts(const std::string& scene_id) {
  auto stub = NewRobotStub(*this);
  return CollectPages<v1::Mount>(
      [this, &stub, &scene_id](const std::string& token) {
        v1::ListMountsRequest request;
        request.set_scene_id(scene_id);
        request.set_page_token(token);
        return UnaryCall(*this, *stub, &RobotStub::ListMounts, request);
      },
      [](const v1::ListMountsResponse& page) -> const auto& { return page.mounts(); });
}

StatusOr<uint64_t> Client::UnmountRobot(const std::string& mount_id) {
  v1::UnmountRobotRequest request;
  request.set_mount_id(mount_id);
  auto stub = NewRobotStub(*this);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &RobotStub::UnmountRobot, request));
  return response.revision();
}

}  // namespace vscan::client
