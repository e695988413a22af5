#include "scan_fuzz_world.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <spdlog/spdlog.h>

#include "robot_registry/bundle_codec.h"

namespace vscan::fuzz {
namespace {

const std::filesystem::path kData = VSCAN_DATA_DIR;

[[noreturn]] void Die(const std::string& what, const Status& status) {
  std::fprintf(stderr, "scan fuzz world: %s: %s\n", what.c_str(), status.ToString().c_str());
  std::abort();
}

template <typename T>
T Must(StatusOr<T> value, const std::string& what) {
  if (!value.ok()) Die(what, value.status());
  return std::move(value).value();
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Die(path.string(), NotFound("cannot read"));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::vector<robot::BundleFile> BundleFiles(const std::filesystem::path& root) {
  std::vector<robot::BundleFile> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (entry.is_regular_file()) {
      files.push_back({std::filesystem::relative(entry.path(), root).generic_string(), ReadFile(entry.path())});
    }
  }
  return files;
}

// A 0.2 m cube centred on its origin.
constexpr std::string_view kCubeObj =
    "v -0.1 -0.1 -0.1\nv 0.1 -0.1 -0.1\nv 0.1 0.1 -0.1\nv -0.1 0.1 -0.1\n"
    "v -0.1 -0.1 0.1\nv 0.1 -0.1 0.1\nv 0.1 0.1 0.1\nv -0.1 0.1 0.1\n"
    "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
    "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

Eigen::Matrix4d Translation(double x, double y, double z) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(x, y, z);
  return m;
}

void AddObjects(ScanFuzzWorld& w) {
  const auto cube = Must(
      w.scenes->AddMesh(kCubeObj, {"cube", geometry::MeshFileFormat::kObj, store::LengthUnit::kMetre, 1.0, 1.0}),
      "cube");
  const auto bunny = Must(w.scenes->AddMesh(ReadFile(kData / "meshes/bunny/bunny_zipper_res2.ply"),
                                            {"bunny", geometry::MeshFileFormat::kPly, store::LengthUnit::kMetre, 1.0, 1.0}),
                          "bunny");
  store::ObjectRecord object;
  object.scene_id = w.scene_id;
  object.mesh_id = cube.mesh_id;
  object.pose = Translation(0, 0, 0.1);
  object.on_table = true;
  Must(w.catalogue->AddObject(object), "cube object");
  object.mesh_id = bunny.mesh_id;
  object.pose = Translation(0.25, 0.1, -0.03);
  object.on_table = false;
  Must(w.catalogue->AddObject(object), "bunny object");
  store::TableRecord table;
  table.enabled = true;
  table.angle_deg = 30;
  Must(w.catalogue->SetTable(w.scene_id, table), "table");
}

// The Panda, mounted beside the objects with its links visible and noisy encoders.
store::RobotRecord AddPanda(ScanFuzzWorld& w) {
  robot_registry::RobotUpload upload;
  upload.urdf_path = "panda.urdf";
  upload.base_link = "panda_link0";
  upload.tip_link = "panda_hand_tcp";
  upload.files = BundleFiles(kData / "robots/panda");
  store::RobotRecord panda = Must(w.robots->AddRobot(std::move(upload)), "panda");
  store::MountRecord mount;
  mount.scene_id = w.scene_id;
  mount.robot_id = panda.robot_id;
  mount.base_pose = Translation(-0.6, 0, -0.2);
  mount.links_visible = true;
  mount.encoder_sigma = {0.01};
  w.default_mount = Must(w.robots->AddMount(mount), "panda mount").first.mount_id;
  w.mounts["panda"] = w.default_mount;
  return panda;
}

// Records as a store written before the physical bounds existed may hold them: uploads and mounts
// refuse these values now, but a scan from them must still end in an error, not an abort. A store
// that refuses them too is fine; their names then fall back to the Panda's mount.
void AddLegacyMounts(ScanFuzzWorld& w, const store::RobotRecord& panda) {
  const auto insert = [&](const std::string& name, store::MountRecord mount) {
    mount.scene_id = w.scene_id;
    if (mount.robot_id.empty()) mount.robot_id = panda.robot_id;
    auto added = w.robot_catalogue->InsertMount(std::move(mount));
    if (added.ok()) w.mounts[name] = added->first.mount_id;
  };
  store::MountRecord base_far;
  base_far.base_pose = Translation(1e19, 0, 0);
  insert("base_1e19", base_far);
  store::MountRecord tool_far;
  tool_far.tool_offset = Translation(0, 0, 1e19);
  insert("tool_1e19", tool_far);

  std::vector<robot::BundleFile> files = BundleFiles(kData / "robots/panda");
  for (robot::BundleFile& file : files) {
    if (file.path != "panda.urdf") continue;
    const std::string from = "xyz=\"0 0 0.333\"";  // panda_joint1's origin
    const size_t at = file.bytes.find(from);
    if (at == std::string::npos) Die("panda.urdf", NotFound("panda_joint1 origin"));
    file.bytes.replace(at, from.size(), "xyz=\"0 0 1e300\"");
  }
  robot::BundleFiles by_path;
  for (robot::BundleFile& file : files) by_path[file.path] = std::move(file.bytes);
  store::RobotRecord far_robot = panda;
  far_robot.bundle_sha256 = Must(w.blobs->Put(robot_registry::EncodeBundle(by_path)), "far bundle");
  auto inserted = w.robot_catalogue->InsertRobot(far_robot);
  if (!inserted.ok()) return;
  store::MountRecord far_mount;
  far_mount.robot_id = inserted->robot_id;
  insert("urdf_origin_1e300", far_mount);
}

constexpr std::string_view kDirPrefix = "vscan-scan-fuzz-";

// A run that aborts (a finding) cannot clean up after itself: remove the directories of runs whose
// process is gone. Directories are named kDirPrefix + pid + "-" + random.
void RemoveStaleDataDirs(const std::filesystem::path& tmp) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(tmp, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(kDirPrefix)) continue;
    const long pid = std::strtol(name.c_str() + kDirPrefix.size(), nullptr, 10);
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
      std::filesystem::remove_all(entry.path(), ec);
    }
  }
}

ScanFuzzWorld* Build() {
  spdlog::set_level(spdlog::level::err);
  const std::filesystem::path tmp = std::filesystem::temp_directory_path();
  RemoveStaleDataDirs(tmp);
  std::string pattern = (tmp / (std::string(kDirPrefix) + std::to_string(::getpid()) + "-XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr) Die(pattern, Unavailable("mkdtemp failed"));
  auto* w = new ScanFuzzWorld;
  w->data_dir = pattern;
  w->options.data_dir = pattern;
  w->options.limits.max_rays_per_scan = kMaxRaysPerScan;
  w->catalogue = Must(store::Catalogue::Open(w->data_dir / "catalogue.sqlite"), "catalogue");
  w->blobs = std::make_unique<store::BlobStore>(w->data_dir / "blobs");
  if (Status s = w->blobs->Open(); !s.ok()) Die("blobs", s);
  // No import sandbox: meshes are parsed in this process.
  w->scenes = std::make_unique<scenes::SceneRegistry>(*w->catalogue, *w->blobs);
  w->robot_catalogue = Must(store::RobotCatalogue::Open(w->data_dir / "catalogue.sqlite"), "robot catalogue");
  w->robots = std::make_unique<robot_registry::RobotRegistry>(*w->robot_catalogue, *w->blobs,
                                                             w->options.limits.max_upload_bytes);
  w->workers = std::make_unique<jobs::WorkerPool>(1);
  w->clouds = Must(store::CloudCatalogue::Open(w->data_dir / "catalogue.sqlite"), "cloud catalogue");
  w->context.reset(new service::ServiceContext(*w->scenes, *w->workers, *w->workers, w->options, *w->robots, w->raster,
                                               *w->clouds, *w->blobs));

  w->scene_id = Must(w->catalogue->CreateScene("fuzz"), "scene").scene_id;
  AddObjects(*w);
  AddLegacyMounts(*w, AddPanda(*w));
  return w;
}

std::filesystem::path* g_data_dir = nullptr;

void RemoveDataDir() {
  std::error_code ec;
  if (g_data_dir) std::filesystem::remove_all(*g_data_dir, ec);
}

}  // namespace

ScanFuzzWorld& World() {
  // Never destroyed: Embree and TBB may still hold threads at exit.
  static ScanFuzzWorld* world = [] {
    ScanFuzzWorld* built = Build();
    g_data_dir = &built->data_dir;
    std::atexit(RemoveDataDir);
    return built;
  }();
  return *world;
}

}  // namespace vscan::fuzz
