#pragma once
// Options, arguments and results of vscan::client::Client calls.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"
#include "vscan/v1/cloud.pb.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/job.pb.h"
#include "vscan/v1/robot.pb.h"
#include "vscan/v1/scan.pb.h"
#include "vscan/v1/scene.pb.h"

namespace vscan::client {

struct ClientOptions {
  // Sent as "authorization: Bearer <token>" on every call when not empty.
  std::string bearer_token;
  // PEM file of the roots to trust; setting it turns TLS on.
  std::string tls_root_cert_path;
  // PEM files of a client certificate (chain) and its private key, presented to a server that
  // requires them (mutual TLS). Both or neither; setting them turns TLS on.
  std::string tls_client_cert_path;
  std::string tls_client_key_path;
  // TLS with the system's default roots (implied by any of the paths above).
  bool use_tls = false;
  // Deadline of each unary call; zero or negative means none.
  std::chrono::milliseconds unary_timeout{30000};
  // Deadline of streaming calls (mesh uploads, scans); zero or negative means none.
  std::chrono::milliseconds stream_timeout{0};
  // Largest message the client accepts; scan chunks may be up to 16 MiB.
  int max_receive_bytes = 64 << 20;
  // HTTP/2 receive window of each stream, fixed from the first byte. gRPC's own flow control
  // (0 here) starts a new channel at 64 KiB and grows it by probing, too late for a one-shot
  // scan, and asks for ever larger frames that cost the client fresh buffers.
  int stream_window_bytes = 8 << 20;
};

// Called with (done, total); total is 0 when unknown.
using ProgressFn = std::function<void(uint64_t done, uint64_t total)>;

struct MeshUploadOptions {
  // Empty: the file name (without directories) when uploading a file.
  std::string name;
  // Unspecified: inferred from the file extension when uploading a file.
  v1::MeshFormat format = v1::MESH_FORMAT_UNSPECIFIED;
  // Required by the server.
  v1::LengthUnit unit = v1::LENGTH_UNIT_UNSPECIFIED;
  double scale = 1.0;
  // The mesh's default material; unset leaves it to the server's default (matte-grey).
  std::optional<v1::Material> material;
  // Bytes per chunk message after the header.
  size_t chunk_bytes = 1 << 20;
};

struct CloudUploadOptions {
  // Empty: the file name (without directories) when uploading a file.
  std::string name;
  // Unspecified: from the file extension (.ply, .pcd) when uploading a file, else the server tells
  // the format from the bytes.
  v1::CloudFormat format = v1::CLOUD_FORMAT_UNSPECIFIED;
  // world_from_sensor, when known.
  std::optional<v1::Pose> sensor_pose;
  // The frame the points are in; unspecified means the world.
  v1::Frame frame = v1::FRAME_UNSPECIFIED;
  // The camera of the scan, when known.
  std::optional<v1::CloudCamera> camera;
  // The scene the cloud was scanned in, if any.
  std::string scene_id;
  // Bytes per chunk message after the header.
  size_t chunk_bytes = 1 << 20;
};

// CLOUD_FORMAT_* from a file name's extension (.ply, .pcd, any case); UNSPECIFIED otherwise.
v1::CloudFormat CloudFormatFromPath(const std::string& path);

struct ObjectPlacement {
  // parent_from_object; unset means identity.
  v1::Pose pose;
  // 0 means 1.
  double scale = 0.0;
  std::string label;
  bool on_table = false;
  // Overrides the mesh's material for this object; unset uses the mesh's.
  std::optional<v1::Material> material;
};

struct ScanCallbacks {
  // Once, when the header arrives.
  std::function<void(const v1::ScanHeader&)> on_header;
  // After each chunk: (points received, points the header announced, 0 when streamed).
  ProgressFn on_progress;
  // When set, each chunk (its arrays checked against its count) goes here instead of into the
  // result's cloud, which then stays empty: for callers that write points out as they arrive. An
  // error stops the scan and is returned.
  std::function<Status(const v1::PointChunk&)> on_chunk;
};

// A scan's per-pixel images (ScanRequest.pixel_images), row-major, header.width x header.height.
struct PixelImages {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> reasons;  // PointStatus values; 0 where the ray met no surface
  std::vector<uint16_t> gray;    // 65535 at full scale
};

struct ScanResult {
  v1::ScanHeader header;
  // In the frame the header names; fields as the header lists them.
  PointCloud cloud;
  v1::ScanStatistics stats;
  // Present when the header says pixel_images.
  std::optional<PixelImages> images;
};

// MESH_FORMAT_* from a file name's extension (.ply, .obj, .stl, any case); UNSPECIFIED otherwise.
v1::MeshFormat MeshFormatFromPath(const std::string& path);

struct RobotUploadOptions {
  // Empty: the URDF's robot name.
  std::string name;
  // Path of the URDF inside the bundle; UploadRobotPath finds it when the directory holds one.
  std::string urdf_path;
  // Empty: the URDF's root link, and the one deepest link below it.
  std::string base_link;
  std::string tip_link;
  // tip_from_tool; unset means identity.
  std::optional<v1::Pose> tool_offset;
  // Largest piece of a file per message.
  size_t chunk_bytes = 1 << 20;
};

// Returns false to stop watching.
using JobEventFn = std::function<bool(const v1::WatchJobResponse&)>;
// Receives an artifact's (or a cloud's) bytes piece by piece; an error stops the download.
using ArtifactSink = std::function<Status(std::string_view)>;

// One file of a robot bundle; path relative to the bundle root, '/' separated.
struct RobotFile {
  std::string path;
  std::string bytes;
};

}  // namespace vscan::client
