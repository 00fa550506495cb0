// Cross-check against an independent library, orocos KDL (Debian liborocos-kdl-dev and
// libkdl-parser-dev, test only): at random configurations of the fixed-base humanoids (the
// HRP-2-like model and kestrel, whose legs are pitch-roll-yaw with offset axes),
//  * each limb chain's joint-space inertia, gravity and Coriolis torques equal KDL's
//    ChainDynParam (legs from the waist/pelvis; arms and head from the chest, with gravity
//    rotated into the chest frame; a chain must be a whole subtree: ChainDynParam ignores
//    side branches, so the torso joints are checked by the tree), and
//  * inverse dynamics of the whole tree equals KDL's TreeIdSolver_RNE,
// to 1e-9 relative (to the largest entry of the compared quantity).
#include "multibody/crba.h"
#include "multibody/data.h"
#include "multibody/kinematics.h"
#include "multibody/rnea.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <gtest/gtest.h>
#include <kdl/chaindynparam.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>

#include <cstdio>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace plantar::multibody {
namespace {

constexpr double kTolerance = 1e-9;

struct Fixture {
  explicit Fixture(const std::string& relative) {
    ModelOptions options;
    options.floating_base = false;
    const std::string path = test::model_path(relative);
    model = build_model_from_urdf(path, options);
    if (!kdl_parser::treeFromFile(path, tree)) {
      throw std::runtime_error("kdl_parser could not read " + path);
    }
  }
  Model model;
  KDL::Tree tree;
};

double relative_error(const Eigen::MatrixXd& ours, const Eigen::MatrixXd& theirs) {
  return (ours - theirs).cwiseAbs().maxCoeff() / std::max(theirs.cwiseAbs().maxCoeff(), 1e-300);
}

struct Chain {
  const char* root;
  const char* tip;
};

struct Robot {
  const char* urdf; ///< relative to models/
  std::vector<Chain> chains;
};

void PrintTo(const Robot& robot, std::ostream* os) {
  *os << robot.urdf;
}

class KdlChains : public ::testing::TestWithParam<Robot> {};

TEST_P(KdlChains, LimbChainsMatchChainDynParam) {
  Fixture fx(GetParam().urdf);
  const Model& model = fx.model;
  Data data(model);
  std::mt19937 rng(2024);
  for (const Chain& c : GetParam().chains) {
    KDL::Chain chain;
    ASSERT_TRUE(fx.tree.getChain(c.root, c.tip, chain)) << c.root << " -> " << c.tip;
    std::vector<int> dofs; // our velocity index of each chain joint
    for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) {
      const KDL::Joint& joint = chain.getSegment(s).getJoint();
      if (joint.getType() != KDL::Joint::None) {
        dofs.push_back(model.idx_v[model.joint_id(joint.getName())]);
      }
    }
    const int n = static_cast<int>(dofs.size());
    ASSERT_EQ(n, static_cast<int>(chain.getNrOfJoints()));
    double err_m = 0.0, err_g = 0.0, err_c = 0.0;
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::VectorXd q = test::random_configuration(model, rng);
      Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv);
      const Eigen::VectorXd v_random = test::random_vector(model.nv, rng);
      KDL::JntArray kq(n), kv(n);
      for (int k = 0; k < n; ++k) {
        v[dofs[k]] = 2.0 * v_random[dofs[k]];
        kq(k) = q[dofs[k]];
        kv(k) = v[dofs[k]];
      }
      // Gravity in the chain root's frame.
      forward_kinematics(model, data, q);
      const Frame& root = model.frames[model.frame_id(c.root)];
      const Eigen::Matrix3d root_rotation = data.oMi[root.body].rotation * root.placement.rotation;
      const Eigen::Vector3d g_root = root_rotation.transpose() * model.gravity;
      KDL::ChainDynParam dyn(chain, KDL::Vector(g_root.x(), g_root.y(), g_root.z()));
      KDL::JntSpaceInertiaMatrix kdl_m(n);
      KDL::JntArray kdl_g(n), kdl_c(n);
      ASSERT_EQ(dyn.JntToMass(kq, kdl_m), 0);
      ASSERT_EQ(dyn.JntToGravity(kq, kdl_g), 0);
      ASSERT_EQ(dyn.JntToCoriolis(kq, kv, kdl_c), 0);

      const Eigen::MatrixXd m_full = crba(model, data, q);
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv);
      const Eigen::VectorXd g_full = rnea(model, data, q, zero, zero);
      const Eigen::VectorXd c_full = rnea(model, data, q, v, zero) - g_full;
      Eigen::MatrixXd m(n, n);
      Eigen::VectorXd g(n), cv(n);
      for (int a = 0; a < n; ++a) {
        g[a] = g_full[dofs[a]];
        cv[a] = c_full[dofs[a]];
        for (int b = 0; b < n; ++b) {
          m(a, b) = m_full(dofs[a], dofs[b]);
        }
      }
      err_m = std::max(err_m, relative_error(m, kdl_m.data));
      err_g = std::max(err_g, relative_error(g, kdl_g.data));
      err_c = std::max(err_c, relative_error(cv, kdl_c.data));
      if (trial == 0) {
        std::printf("%s -> %s (%d joints): M(0,0) ours %.15g KDL %.15g; g[0] ours %.15g KDL %.15g; "
                    "(Cv)[0] ours %.15g KDL %.15g\n",
                    c.root, c.tip, n, m(0, 0), kdl_m(0, 0), g[0], kdl_g(0), cv[0], kdl_c(0));
      }
    }
    std::printf("%s, %s -> %s: max relative error over 10 configurations: M %.2e, G %.2e, "
                "C v %.2e (tol %.0e)\n",
                GetParam().urdf, c.root, c.tip, err_m, err_g, err_c, kTolerance);
    EXPECT_LT(err_m, kTolerance);
    EXPECT_LT(err_g, kTolerance);
    EXPECT_LT(err_c, kTolerance);
  }
}

INSTANTIATE_TEST_SUITE_P(Humanoids, KdlChains,
                         ::testing::Values(Robot{"hrp2/hrp2.urdf",
                                                 {{"BODY", "RLEG_LINK5"},
                                                  {"BODY", "LLEG_LINK5"},
                                                  {"CHEST_LINK1", "RARM_LINK6"},
                                                  {"CHEST_LINK1", "LARM_LINK6"},
                                                  {"CHEST_LINK1", "HEAD_LINK1"}}},
                                           Robot{"kestrel/kestrel.urdf",
                                                 {{"pelvis", "r_foot"},
                                                  {"pelvis", "l_foot"},
                                                  {"chest", "r_hand"},
                                                  {"chest", "l_hand"},
                                                  {"chest", "head"}}}),
                         [](const ::testing::TestParamInfo<Robot>& info) {
                           const std::string urdf = info.param.urdf;
                           return urdf.substr(0, urdf.find('/'));
                         });

class KdlTree : public ::testing::TestWithParam<const char*> {};

// The HRP-2-like tree, kestrel's, and the branched test robot (rotated joint origins and inertias,
// a prismatic joint, a continuous joint with a slanted axis, fixed joints with masses).
TEST_P(KdlTree, WholeTreeInverseDynamicsMatchesTreeIdSolverRne) {
  Fixture fx(GetParam());
  const Model& model = fx.model;
  Data data(model);
  ASSERT_EQ(static_cast<int>(fx.tree.getNrOfJoints()), model.nv);
  // KDL's joint numbering -> ours, by joint name.
  std::vector<int> ours_of_kdl(model.nv, -1);
  for (const auto& [name, element] : fx.tree.getSegments()) {
    const KDL::Joint& joint = GetTreeElementSegment(element).getJoint();
    if (joint.getType() != KDL::Joint::None) {
      ours_of_kdl[GetTreeElementQNr(element)] = model.idx_v[model.joint_id(joint.getName())];
    }
  }
  const Eigen::Vector3d g = model.gravity;
  KDL::TreeIdSolver_RNE solver(fx.tree, KDL::Vector(g.x(), g.y(), g.z()));
  std::mt19937 rng(77);
  double worst = 0.0;
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd q = test::random_configuration(model, rng);
    const Eigen::VectorXd v = 2.0 * test::random_vector(model.nv, rng);
    const Eigen::VectorXd a = 5.0 * test::random_vector(model.nv, rng);
    KDL::JntArray kq(model.nv), kv(model.nv), ka(model.nv), ktau(model.nv);
    for (int k = 0; k < model.nv; ++k) {
      kq(k) = q[ours_of_kdl[k]];
      kv(k) = v[ours_of_kdl[k]];
      ka(k) = a[ours_of_kdl[k]];
    }
    KDL::WrenchMap no_external;
    ASSERT_GE(solver.CartToJnt(kq, kv, ka, no_external, ktau), 0);
    const Eigen::VectorXd tau = rnea(model, data, q, v, a);
    Eigen::VectorXd tau_kdl(model.nv);
    for (int k = 0; k < model.nv; ++k) {
      tau_kdl[ours_of_kdl[k]] = ktau(k);
    }
    worst = std::max(worst, relative_error(tau, tau_kdl));
    if (trial == 0) {
      std::printf("tree RNEA, first configuration: |tau| ours %.15g KDL %.15g\n", tau.norm(),
                  tau_kdl.norm());
    }
  }
  std::printf("%s, whole tree (%d joints): max relative error of tau vs TreeIdSolver_RNE over 10 "
              "configurations %.2e (tol %.0e)\n",
              GetParam(), model.nv, worst, kTolerance);
  EXPECT_LT(worst, kTolerance);
}

INSTANTIATE_TEST_SUITE_P(Models, KdlTree,
                         ::testing::Values("hrp2/hrp2.urdf", "kestrel/kestrel.urdf",
                                           "test/branched_robot.urdf"));

} // namespace
} // namespace plantar::multibody
