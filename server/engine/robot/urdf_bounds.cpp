#include "robot/urdf_bounds.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Core>
#include <urdf_model/model.h>

#include "vscan/common/physical_limits.h"

namespace vscan::robot {
namespace {

std::string Bound() {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", kMaxCoordinateM);
  return text;
}

Status CheckOrigin(const urdf::Pose& origin, const std::string& field) {
  RETURN_IF_ERROR(CheckPosition(Eigen::Vector3d(origin.position.x, origin.position.y, origin.position.z),
                                field + ".xyz"));
  // urdfdom keeps rpy only as the quaternion it makes of it.
  const urdf::Rotation& r = origin.rotation;
  if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z) || !std::isfinite(r.w)) {
    return InvalidArgument(field + ".rpy: NaN or infinite value");
  }
  return Status::Ok();
}

Status CheckLength(double value, const std::string& field) {
  if (!std::isfinite(value) || value < 0 || value > kMaxCoordinateM) {
    return InvalidArgument(field + ": must be finite, >= 0 and <= " + Bound() + " m");
  }
  return Status::Ok();
}

Status CheckGeometry(const urdf::Geometry& geometry, const std::string& field) {
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const urdf::Vector3& d = static_cast<const urdf::Box&>(geometry).dim;
      for (double v : {d.x, d.y, d.z}) RETURN_IF_ERROR(CheckLength(v, field + ".box.size"));
      return Status::Ok();
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      RETURN_IF_ERROR(CheckLength(cylinder.radius, field + ".cylinder.radius"));
      return CheckLength(cylinder.length, field + ".cylinder.length");
    }
    case urdf::Geometry::SPHERE:
      return CheckLength(static_cast<const urdf::Sphere&>(geometry).radius, field + ".sphere.radius");
    case urdf::Geometry::MESH: {
      // A factor on coordinates: a mesh of 1 m stays within the coordinate bound (mirroring is allowed).
      const urdf::Vector3& s = static_cast<const urdf::Mesh&>(geometry).scale;
      for (double v : {s.x, s.y, s.z}) {
        if (!std::isfinite(v) || std::abs(v) > kMaxCoordinateM) {
          return InvalidArgument(field + ".mesh.scale: each factor must be finite with magnitude <= " + Bound());
        }
      }
      return Status::Ok();
    }
  }
  return Status::Ok();
}

template <typename Element>
Status CheckElements(const std::vector<std::shared_ptr<Element>>& elements, const std::string& link, const char* role) {
  for (size_t i = 0; i < elements.size(); ++i) {
    if (elements[i] == nullptr) continue;
    const std::string field = "links['" + link + "']." + role + "[" + std::to_string(i) + "]";
    RETURN_IF_ERROR(CheckOrigin(elements[i]->origin, field + ".origin"));
    if (elements[i]->geometry != nullptr) RETURN_IF_ERROR(CheckGeometry(*elements[i]->geometry, field));
  }
  return Status::Ok();
}

Status CheckJoint(const urdf::Joint& joint) {
  const std::string field = "joints['" + joint.name + "']";
  RETURN_IF_ERROR(CheckOrigin(joint.parent_to_joint_origin_transform, field + ".origin"));
  if (!std::isfinite(joint.axis.x) || !std::isfinite(joint.axis.y) || !std::isfinite(joint.axis.z)) {
    return InvalidArgument(field + ".axis: NaN or infinite value");
  }
  // A prismatic joint at its limit moves the links beyond it by that many metres.
  if (joint.type == urdf::Joint::PRISMATIC && joint.limits != nullptr &&
      !(std::abs(joint.limits->lower) <= kMaxCoordinateM && std::abs(joint.limits->upper) <= kMaxCoordinateM)) {
    return InvalidArgument(field + ".limit: a prismatic joint's lower and upper must be finite and within +-" +
                           Bound() + " m");
  }
  return Status::Ok();
}

}  // namespace

Status CheckUrdfBounds(const urdf::ModelInterface& model) {
  // std::maps: the first offender in name order is the one reported.
  for (const auto& [name, joint] : model.joints_) RETURN_IF_ERROR(CheckJoint(*joint));
  for (const auto& [name, link] : model.links_) {
    RETURN_IF_ERROR(CheckElements(link->visual_array, name, "visual"));
    RETURN_IF_ERROR(CheckElements(link->collision_array, name, "collision"));
  }
  return Status::Ok();
}

}  // namespace vscan::robot
