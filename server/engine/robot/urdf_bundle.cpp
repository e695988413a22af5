#include "robot/urdf_bundle.h"

#include <urdf_model/model.h>

#include "robot/urdf_bounds.h"
#include "robot/urdf_parse.h"
#include "robot/urdf_tree.h"
#include "robot/urdf_tree_precheck.h"

namespace vscan::robot {
namespace {

std::string FileField(size_t i) { return "files[" + std::to_string(i) + "].path"; }

Status CheckLimits(const std::vector<BundleFile>& files, const BundleLimits& limits) {
  if (files.size() > limits.max_files) {
    return ResourceExhausted("files", std::to_string(files.size()) + " files exceed the limit of " +
                             std::to_string(limits.max_files));
  }
  uint64_t total = 0;
  for (const BundleFile& file : files) total += file.bytes.size() + file.path.size();
  if (total > limits.max_total_bytes) {
    return ResourceExhausted("files", "bundle of " + std::to_string(total) + " bytes exceeds the limit of " +
                             std::to_string(limits.max_total_bytes));
  }
  return Status::Ok();
}

StatusOr<BundleFiles> NormalizeFiles(std::vector<BundleFile> files) {
  BundleFiles out;
  std::map<std::string, size_t, std::less<>> first_index;
  for (size_t i = 0; i < files.size(); ++i) {
    ASSIGN_OR_RETURN(std::string path, NormalizeBundlePath(files[i].path, FileField(i)));
    const auto [it, inserted] = first_index.emplace(path, i);
    if (!inserted) {
      return InvalidArgument(FileField(i) + ": '" + files[i].path + "' names the same file as files[" +
                             std::to_string(it->second) + "].path");
    }
    out.emplace(std::move(path), std::move(files[i].bytes));
  }
  return out;
}

Status CollectMesh(const std::string& link, const char* role, int index, const urdf::GeometrySharedPtr& geometry,
                   const std::string& urdf_dir, UrdfBundle& bundle) {
  if (geometry == nullptr || geometry->type != urdf::Geometry::MESH) return Status::Ok();
  const auto& mesh = static_cast<const urdf::Mesh&>(*geometry);
  const std::string field = "links['" + link + "']." + role + "[" + std::to_string(index) + "].mesh";
  ASSIGN_OR_RETURN(MeshLocation location, ResolveMeshReference(mesh.filename, urdf_dir, bundle.files, field));
  MeshReference ref{link, role, index, mesh.filename, location.found ? location.bundle_path : std::string(),
                    Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z)};
  if (!location.found) {
    bundle.warnings.push_back(field + ": '" + mesh.filename + "' not in the bundle (looked for '" +
                              location.bundle_path + "'); the link has no " + role + " geometry");
  }
  bundle.meshes.push_back(std::move(ref));
  return Status::Ok();
}

Status CollectMeshes(UrdfBundle& bundle) {
  const std::string urdf_dir = ParentDirectory(bundle.urdf_path);
  // links_ is a std::map, so meshes and warnings come out in link-name order.
  for (const auto& [name, link] : bundle.model->links_) {
    for (size_t i = 0; i < link->visual_array.size(); ++i) {
      if (link->visual_array[i] == nullptr) continue;
      RETURN_IF_ERROR(CollectMesh(name, "visual", static_cast<int>(i), link->visual_array[i]->geometry, urdf_dir, bundle));
    }
    for (size_t i = 0; i < link->collision_array.size(); ++i) {
      if (link->collision_array[i] == nullptr) continue;
      RETURN_IF_ERROR(
          CollectMesh(name, "collision", static_cast<int>(i), link->collision_array[i]->geometry, urdf_dir, bundle));
    }
  }
  return Status::Ok();
}

}  // namespace

StatusOr<UrdfBundle> LoadUrdfBundle(std::string_view urdf_path, std::vector<BundleFile> files,
                                    const BundleLimits& limits) {
  RETURN_IF_ERROR(CheckLimits(files, limits));
  UrdfBundle bundle;
  ASSIGN_OR_RETURN(bundle.urdf_path, NormalizeBundlePath(urdf_path, "urdf_path"));
  ASSIGN_OR_RETURN(bundle.files, NormalizeFiles(std::move(files)));
  const auto urdf_file = bundle.files.find(bundle.urdf_path);
  if (urdf_file == bundle.files.end()) {
    return InvalidArgument("urdf_path", "'" + bundle.urdf_path + "' is not among the bundle's files");
  }
  RETURN_IF_ERROR(CheckUrdfTreeBeforeParse(urdf_file->second));
  ASSIGN_OR_RETURN(bundle.model, ParseUrdfXml(urdf_file->second));
  RETURN_IF_ERROR(CheckUrdfTree(*bundle.model));
  RETURN_IF_ERROR(CheckUrdfBounds(*bundle.model));
  RETURN_IF_ERROR(CollectMeshes(bundle));
  return bundle;
}

}  // namespace vscan::robot
