#include "ik_bench_kdl.h"

#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <urdf_model/model.h>

namespace vscan::bench {
namespace {

KDL::Frame ToKdl(const Pose3& pose) {
  const Eigen::Matrix3d& R = pose.linear();
  const Eigen::Vector3d& t = pose.translation();
  return KDL::Frame(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)),
                    KDL::Vector(t.x(), t.y(), t.z()));
}

}  // namespace

struct KdlIk::Impl {
  KDL::Chain chain;
  KDL::JntArray lower, upper;
  std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk;
  std::unique_ptr<KDL::ChainIkSolverVel_pinv> vel;
  std::unique_ptr<KDL::ChainIkSolverPos_NR_JL> ik;
  std::mt19937_64 rng{2024};
};

KdlIk::KdlIk(const urdf::ModelInterface& model, const std::string& base, const std::string& tip, int max_iterations,
             double eps)
    : impl_(std::make_unique<Impl>()) {
  KDL::Tree tree;
  if (!kdl_parser::treeFromUrdfModel(model, tree) || !tree.getChain(base, tip, impl_->chain)) {
    std::fprintf(stderr, "KDL could not build %s -> %s\n", base.c_str(), tip.c_str());
    std::exit(1);
  }
  const unsigned n = impl_->chain.getNrOfJoints();
  impl_->lower.resize(n);
  impl_->upper.resize(n);
  unsigned j = 0;
  for (const KDL::Segment& segment : impl_->chain.segments) {
    if (segment.getJoint().getType() == KDL::Joint::None) continue;
    const urdf::JointConstSharedPtr joint = model.getJoint(segment.getJoint().getName());
    const bool continuous = joint->type == urdf::Joint::CONTINUOUS;
    impl_->lower(j) = continuous ? -std::numbers::pi : joint->limits->lower;
    impl_->upper(j) = continuous ? std::numbers::pi : joint->limits->upper;
    ++j;
  }
  impl_->fk = std::make_unique<KDL::ChainFkSolverPos_recursive>(impl_->chain);
  impl_->vel = std::make_unique<KDL::ChainIkSolverVel_pinv>(impl_->chain);
  impl_->ik = std::make_unique<KDL::ChainIkSolverPos_NR_JL>(impl_->chain, impl_->lower, impl_->upper, *impl_->fk,
                                                            *impl_->vel, max_iterations, eps);
}

KdlIk::~KdlIk() = default;

bool KdlIk::Solve(const Pose3& target, const Eigen::VectorXd& seed, Eigen::VectorXd* q) {
  KDL::JntArray in(seed.size()), out(seed.size());
  in.data = seed;
  const int rc = impl_->ik->CartToJnt(in, ToKdl(target), out);
  *q = out.data;
  return rc >= 0;
}

bool KdlIk::SolveWithRestarts(const Pose3& target, const Eigen::VectorXd& seed, std::chrono::microseconds budget,
                              Eigen::VectorXd* q) {
  const auto deadline = std::chrono::steady_clock::now() + budget;
  Eigen::VectorXd start = seed;
  while (true) {
    if (Solve(target, start, q)) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    for (int i = 0; i < start.size(); ++i) {
      start[i] = std::uniform_real_distribution<double>(impl_->lower(i), impl_->upper(i))(impl_->rng);
    }
  }
}

}  // namespace vscan::bench
