#include "robot_registry/link_geometry.h"

#include <urdf_model/model.h>

#include <algorithm>
#include <cmath>
#include <cctype>
#include <map>
#include <numbers>

#include <Eigen/Geometry>

#include "vscan/common/physical_limits.h"

namespace vscan::robot_registry {
namespace {

constexpr int kRoundSegments = 32;
constexpr int kSphereStacks = 16;

Pose3 ToPose(const urdf::Pose& p) {
  double x, y, z, w;
  p.rotation.getQuaternion(x, y, z, w);
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return pose;
}

TriangleMesh BoxMesh(const Eigen::Vector3d& size) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back(float((i & 1 ? 0.5 : -0.5) * size.x()), float((i & 2 ? 0.5 : -0.5) * size.y()),
                               float((i & 4 ? 0.5 : -0.5) * size.z()));
  }
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

// Along z, centred on the origin (the URDF's convention).
TriangleMesh CylinderMesh(double radius, double length) {
  TriangleMesh mesh;
  const auto n = static_cast<uint32_t>(kRoundSegments);
  for (uint32_t i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    for (double z : {-0.5 * length, 0.5 * length}) {
      mesh.vertices.emplace_back(float(radius * std::cos(a)), float(radius * std::sin(a)), float(z));
    }
  }
  const uint32_t bottom = 2 * n, top = 2 * n + 1;
  mesh.vertices.emplace_back(0.f, 0.f, float(-0.5 * length));
  mesh.vertices.emplace_back(0.f, 0.f, float(0.5 * length));
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    mesh.triangles.push_back({2 * i, 2 * j, 2 * i + 1});
    mesh.triangles.push_back({2 * i + 1, 2 * j, 2 * j + 1});
    mesh.triangles.push_back({bottom, 2 * j, 2 * i});
    mesh.triangles.push_back({top, 2 * i + 1, 2 * j + 1});
  }
  return mesh;
}

TriangleMesh SphereMesh(double radius) {
  TriangleMesh mesh;
  const auto slices = static_cast<uint32_t>(kRoundSegments), stacks = static_cast<uint32_t>(kSphereStacks);
  for (uint32_t s = 0; s <= stacks; ++s) {
    const double polar = std::numbers::pi * s / stacks;
    for (uint32_t i = 0; i < slices; ++i) {
      const double a = 2 * std::numbers::pi * i / slices;
      mesh.vertices.emplace_back(float(radius * std::sin(polar) * std::cos(a)),
                                 float(radius * std::sin(polar) * std::sin(a)), float(radius * std::cos(polar)));
    }
  }
  for (uint32_t s = 0; s < stacks; ++s) {
    for (uint32_t i = 0; i < slices; ++i) {
      const uint32_t j = (i + 1) % slices;
      const uint32_t a = s * slices + i, b = s * slices + j, c = (s + 1) * slices + i, d = (s + 1) * slices + j;
      if (s > 0) mesh.triangles.push_back({a, c, b});
      if (s + 1 < stacks) mesh.triangles.push_back({b, c, d});
    }
  }
  return mesh;
}

bool WithinMeshBounds(const TriangleMesh& mesh) {
  for (const Eigen::Vector3f& v : mesh.vertices) {
    if (!v.allFinite() || v.cwiseAbs().maxCoeff() > kMaxMeshCoordinateM) return false;
  }
  return true;
}

// Imports each bundle file once and keeps one scaled copy per scale.
class MeshLoader {
 public:
  MeshLoader(const robot::UrdfBundle& bundle, const LinkMeshImporter& import, std::vector<std::string>& warnings)
      : bundle_(bundle), import_(import), warnings_(warnings) {}

  std::shared_ptr<const TriangleMesh> Load(const std::string& field, const std::string& path,
                                           const Eigen::Vector3d& scale) {
    const auto key = std::make_pair(path, std::vector<double>{scale.x(), scale.y(), scale.z()});
    if (auto it = scaled_.find(key); it != scaled_.end()) return it->second;
    auto raw = Raw(field, path);
    if (raw == nullptr) return nullptr;
    auto mesh = std::make_shared<TriangleMesh>(*raw);
    for (Eigen::Vector3f& v : mesh->vertices) v = v.cwiseProduct(scale.cast<float>());
    // Mesh and scale are each bounded where they enter; their product is checked here.
    if (!WithinMeshBounds(*mesh)) {
      warnings_.push_back(field + ": '" + path + "' scaled by its mesh scale reaches beyond " +
                          std::to_string(static_cast<int>(kMaxMeshCoordinateM)) + " m; the shape is left out");
      mesh = nullptr;
    }
    scaled_.emplace(key, mesh);
    return mesh;
  }

 private:
  std::shared_ptr<const TriangleMesh> Raw(const std::string& field, const std::string& path) {
    if (auto it = raw_.find(path); it != raw_.end()) return it->second;
    std::shared_ptr<const TriangleMesh> mesh;
    const auto file = bundle_.files.find(path);
    if (file != bundle_.files.end()) {
      auto imported = import_(file->second, path);
      if (imported.ok()) {
        mesh = std::make_shared<const TriangleMesh>(std::move(imported).value());
      } else {
        warnings_.push_back(field + ": '" + path + "': " + imported.status().message());
      }
    }
    raw_.emplace(path, mesh);
    return mesh;
  }

  const robot::UrdfBundle& bundle_;
  const LinkMeshImporter& import_;
  std::vector<std::string>& warnings_;
  std::map<std::string, std::shared_ptr<const TriangleMesh>> raw_;
  std::map<std::pair<std::string, std::vector<double>>, std::shared_ptr<const TriangleMesh>> scaled_;
};

// The shapes of one geometry element; empty when it cannot be used (a warning says why, unless
// the bundle lacks the file, which the upload already warned about).
std::vector<LinkShape> Shapes(const urdf::GeometrySharedPtr& geometry, const urdf::Pose& origin,
                              const std::string& field, const std::string& link, const char* role, int index,
                              const robot::UrdfBundle& bundle, MeshLoader& loader) {
  if (geometry == nullptr) return {};
  const Pose3 link_from_shape = ToPose(origin);
  std::shared_ptr<const TriangleMesh> mesh;
  switch (geometry->type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(*geometry);
      mesh = std::make_shared<const TriangleMesh>(BoxMesh({box.dim.x, box.dim.y, box.dim.z}));
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(*geometry);
      mesh = std::make_shared<const TriangleMesh>(CylinderMesh(cylinder.radius, cylinder.length));
      break;
    }
    case urdf::Geometry::SPHERE:
      mesh = std::make_shared<const TriangleMesh>(SphereMesh(static_cast<const urdf::Sphere&>(*geometry).radius));
      break;
    case urdf::Geometry::MESH: {
      for (const robot::MeshReference& ref : bundle.meshes) {
        if (ref.link != link || ref.role != role || ref.index != index) continue;
        if (!ref.bundle_path.empty()) mesh = loader.Load(field, ref.bundle_path, ref.scale);
      }
      break;
    }
  }
  if (mesh == nullptr || mesh->empty()) return {};
  return {LinkShape{std::move(mesh), link_from_shape}};
}

template <typename Element>
std::vector<LinkShape> AllShapes(const std::vector<std::shared_ptr<Element>>& elements, const std::string& link,
                                 const char* role, const robot::UrdfBundle& bundle, MeshLoader& loader) {
  std::vector<LinkShape> out;
  for (size_t i = 0; i < elements.size(); ++i) {
    if (elements[i] == nullptr) continue;
    const std::string field = "links['" + link + "']." + role + "[" + std::to_string(i) + "]";
    for (LinkShape& shape : Shapes(elements[i]->geometry, elements[i]->origin, field, link, role,
                                   static_cast<int>(i), bundle, loader)) {
      out.push_back(std::move(shape));
    }
  }
  return out;
}

robot::JointType JointTypeOf(const urdf::Joint& joint) {
  switch (joint.type) {
    case urdf::Joint::REVOLUTE: return robot::JointType::kRevolute;
    case urdf::Joint::CONTINUOUS: return robot::JointType::kContinuous;
    case urdf::Joint::PRISMATIC: return robot::JointType::kPrismatic;
    default: return robot::JointType::kFixed;
  }
}

}  // namespace

StatusOr<RobotLinks> LoadRobotLinks(const robot::UrdfBundle& bundle, const robot::KinematicChain& chain,
                                    const LinkMeshImporter& import) {
  const urdf::ModelInterface& model = *bundle.model;
  RobotLinks out;
  std::map<std::string, int> index;
  for (const auto& [name, link] : model.links_) {
    index[name] = static_cast<int>(out.names.size());
    out.names.push_back(name);
  }
  const auto base = index.find(chain.base_link());
  if (base == index.end()) return DataLoss("robot: base link '" + chain.base_link() + "' is not in the URDF");
  out.base = base->second;

  out.joints.resize(out.names.size());
  MeshLoader loader(bundle, import, out.warnings);
  for (const auto& [name, link] : model.links_) {
    const int i = index.at(name);
    LinkJoint& joint = out.joints[static_cast<size_t>(i)];
    if (const auto& parent = link->parent_joint; parent != nullptr) {
      joint.parent = index.at(parent->parent_link_name);
      joint.parent_from_joint = ToPose(parent->parent_to_joint_origin_transform);
      joint.type = JointTypeOf(*parent);
      joint.axis = Eigen::Vector3d(parent->axis.x, parent->axis.y, parent->axis.z);
      if (joint.axis.norm() > 0) joint.axis.normalize();
      for (size_t j = 0; j < chain.joints().size(); ++j) {
        if (chain.joints()[j].name == parent->name) joint.chain_joint = static_cast<int>(j);
      }
    }
    auto visual = AllShapes(link->visual_array, name, "visual", bundle, loader);
    auto collision = AllShapes(link->collision_array, name, "collision", bundle, loader);
    if (visual.empty() && !collision.empty() && !link->visual_array.empty()) {
      out.warnings.push_back("links['" + name + "']: visual geometry unusable; scans show its collision geometry");
    }
    out.visual.push_back(visual.empty() ? collision : visual);
    out.collision.push_back(collision.empty() ? visual : collision);
  }
  if (out.names.size() > kMaxVisibleLinks) {
    out.warnings.push_back("links: only the first " + std::to_string(kMaxVisibleLinks) + " links appear in scans");
  }
  return out;
}

std::vector<Pose3> LinkPoses(const RobotLinks& links, const Eigen::VectorXd& q) {
  const size_t n = links.names.size();
  std::vector<Pose3> root_from_link(n, Pose3::Identity());
  std::vector<char> done(n, 0);
  // Parents before children: resolve each link's ancestry on demand.
  std::vector<size_t> pending;
  for (size_t i = 0; i < n; ++i) {
    for (size_t at = i; !done[at];) {
      const int parent = links.joints[at].parent;
      if (parent < 0 || done[static_cast<size_t>(parent)]) {
        const LinkJoint& joint = links.joints[at];
        Pose3 motion = Pose3::Identity();
        const double value = joint.chain_joint >= 0 && joint.chain_joint < q.size() ? q[joint.chain_joint] : 0.0;
        if (joint.type == robot::JointType::kRevolute || joint.type == robot::JointType::kContinuous) {
          motion.linear() = Eigen::AngleAxisd(value, joint.axis).toRotationMatrix();
        } else if (joint.type == robot::JointType::kPrismatic) {
          motion.translation() = value * joint.axis;
        }
        root_from_link[at] =
            (parent < 0 ? Pose3::Identity() : root_from_link[static_cast<size_t>(parent)]) * joint.parent_from_joint *
            motion;
        done[at] = 1;
        if (pending.empty()) break;
        at = pending.back();
        pending.pop_back();
      } else if (pending.size() == n) {
        // Parents that loop (refused at upload): leave these links where they are.
        pending.clear();
        break;
      } else {
        pending.push_back(at);
        at = static_cast<size_t>(parent);
      }
    }
  }
  const Pose3 base_from_root = root_from_link[static_cast<size_t>(links.base)].inverse();
  std::vector<Pose3> out(n);
  for (size_t i = 0; i < n; ++i) out[i] = base_from_root * root_from_link[i];
  return out;
}

uint32_t LinkInstanceIdBase(std::string_view mount_id) {
  uint32_t bits = 0;
  int digits = 0;
  for (char c : mount_id.substr(std::min<size_t>(mount_id.find('_') + 1, mount_id.size()))) {
    if (digits == 6) break;
    const int value = std::isdigit(static_cast<unsigned char>(c)) ? c - '0'
                      : (c >= 'a' && c <= 'f')                     ? c - 'a' + 10
                                                                   : -1;
    if (value < 0) break;
    bits = bits << 4 | static_cast<uint32_t>(value);
    ++digits;
  }
  return kLinkInstanceIdBit | (bits >> 1) << 8;
}

}  // namespace vscan::robot_registry
