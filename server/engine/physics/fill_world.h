#pragma once
// What the fill loop asks of a physics world: parts added and removed, fixed steps, their states,
// and the deepest contacts after a final collision pass. The bin is part of the world.

#include <cstddef>
#include <memory>
#include <utility>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::physics {

struct BodyState {
  Pose3 world_from_body = Pose3::Identity();  // body frame: the part's centre of mass
  double linear_speed = 0.0;                  // m/s
  double angular_speed = 0.0;                 // rad/s
};

struct ContactDepths {
  double part_part = 0.0;  // deepest overlap, metres, >= 0
  double part_bin = 0.0;
};

class FillWorld {
 public:
  virtual ~FillWorld() = default;
  // type indexes the part geometries the world was made with. Returns the body's handle.
  virtual size_t AddPart(size_t type, const Pose3& world_from_body) = 0;
  virtual void RemovePart(size_t body) = 0;
  virtual void Step() = 0;
  // Linear and angular damping (per second, 0..1) of every part from now on.
  virtual void SetDamping(double damping) = 0;
  virtual BodyState State(size_t body) const = 0;
  virtual ContactDepths DeepestContacts() = 0;
};

// A FillWorld that passes every call on to another; a decorator overrides what it watches and calls
// the inner world through inner().
class ForwardingFillWorld : public FillWorld {
 public:
  explicit ForwardingFillWorld(std::unique_ptr<FillWorld> world) : world_(std::move(world)) {}
  size_t AddPart(size_t type, const Pose3& world_from_body) override { return world_->AddPart(type, world_from_body); }
  void RemovePart(size_t body) override { world_->RemovePart(body); }
  void Step() override { world_->Step(); }
  void SetDamping(double damping) override { world_->SetDamping(damping); }
  BodyState State(size_t body) const override { return world_->State(body); }
  ContactDepths DeepestContacts() override { return world_->DeepestContacts(); }

 protected:
  FillWorld& inner() { return *world_; }
  const FillWorld& inner() const { return *world_; }

 private:
  std::unique_ptr<FillWorld> world_;
};

}  // namespace vscan::physics
