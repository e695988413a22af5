#include "kdl_oracle.h"

#include <cstdio>
#include <cstdlib>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>

namespace vscan::robot::testing {

struct KdlOracle::Impl {
  KDL::Chain chain;
  std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk;
  std::unique_ptr<KDL::ChainJntToJacSolver> jac;
};

KdlOracle::KdlOracle(const urdf::ModelInterface& model, const std::string& base, const std::string& tip)
    : impl_(std::make_unique<Impl>()) {
  KDL::Tree tree;
  if (!kdl_parser::treeFromUrdfModel(model, tree) || !tree.getChain(base, tip, impl_->chain)) {
    std::fprintf(stderr, "KDL could not build %s -> %s\n", base.c_str(), tip.c_str());
    std::abort();
  }
  impl_->fk = std::make_unique<KDL::ChainFkSolverPos_recursive>(impl_->chain);
  impl_->jac = std::make_unique<KDL::ChainJntToJacSolver>(impl_->chain);
}

KdlOracle::~KdlOracle() = default;

int KdlOracle::dof() const { return static_cast<int>(impl_->chain.getNrOfJoints()); }

Pose3 KdlOracle::Fk(const Eigen::VectorXd& q) const {
  KDL::JntArray joints(dof());
  joints.data = q;
  KDL::Frame frame;
  impl_->fk->JntToCart(joints, frame);
  Pose3 pose = Pose3::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) pose.linear()(r, c) = frame.M(r, c);
    pose.translation()[r] = frame.p[r];
  }
  return pose;
}

Eigen::Matrix<double, 6, Eigen::Dynamic> KdlOracle::Jacobian(const Eigen::VectorXd& q) const {
  KDL::JntArray joints(dof());
  joints.data = q;
  KDL::Jacobian jacobian(dof());
  impl_->jac->JntToJac(joints, jacobian);
  return jacobian.data;
}

}  // namespace vscan::robot::testing
