// The contact problem the stepper builds (W = G G^T + blockdiag(A C A^T / dt^2), v_free,c)
// and its velocity update v+ = v_free + M_eff^-1 J_c^T p, against a dense reference: J_c from
// point_jacobian row by row, L from Eigen's LLT of M_eff assembled here, J_c M_eff^-1 J_c^T =
// g g^T with g = J_c L^-T, the patch block from the dense Kronecker product
// (I (x) a) C (I (x) a)^T. The stepper derives a reduced G (6 columns per contact body,
// G G^T = g g^T) from one Jacobian per body and keeps the patch block in the body frame with
// its rotation; the two must agree to round-off (1e-12 relative).
#include "coupling/pad_state.h"
#include "multibody/crba.h"
#include "multibody/data.h"
#include "multibody/jacobian.h"
#include "multibody/kinematics.h"
#include "multibody/rnea.h"
#include "multibody/stepper.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

namespace plantar::multibody {
namespace {

struct Candidate {
  int body;
  Eigen::Vector3d position;
};

/// max |a - b| / max |b|.
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

class ContactRows : public ::testing::Test {
protected:
  ContactRows() : model(build_model_from_urdf(test::model_path("hrp2/hrp2.urdf"))), rng(7) {}

  /// Dense reference for the step from (q0, v0): M_eff, v_free, J_c (patch nodes first).
  void reference(const Eigen::VectorXd& q0, const Eigen::VectorXd& v0) {
    Data d(model);
    crba(model, d, q0);
    nonlinear_effects(model, d, q0, v0);
    const int nv = model.nv;
    Eigen::MatrixXd m_eff = d.mass_matrix;
    Eigen::VectorXd rhs = d.mass_matrix * v0 + dt * (tau - d.bias);
    for (int i = 1; i < model.n_bodies; ++i) {
      if (model.joint_type[i] == JointType::FreeFlyer) {
        continue;
      }
      const int iq = model.idx_q[i], iv = model.idx_v[i];
      const double kp = gains.stiffness[iv], kd = gains.damping[iv];
      const double ks = model.passive_stiffness[iv], ds = model.passive_damping[iv];
      m_eff(iv, iv) += dt * (kd + ds) + dt * dt * (kp + ks);
      rhs[iv] += dt * (kp * (q_ref[iq] - q0[iq]) + ks * (model.passive_rest[iv] - q0[iq]) +
                       kd * v_ref[iv]);
    }
    llt.compute(m_eff);
    ASSERT_EQ(llt.info(), Eigen::Success);
    v_free = llt.solve(rhs);
    const int rows = 3 * static_cast<int>(candidates.size());
    jc.setZero(rows, nv);
    Eigen::MatrixXd j3(3, nv);
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      point_jacobian(model, d, candidates[k].body, candidates[k].position, j3);
      jc.row(3 * k) = j3.row(2); // n = z
      jc.row(3 * k + 1) = j3.row(0);
      jc.row(3 * k + 2) = j3.row(1);
    }
    // G = J_c L^-T = (L^-1 J_c^T)^T.
    g = llt.matrixL().solve(Eigen::MatrixXd(jc.transpose())).transpose();
    rotation = d.oMi[patch_body].rotation;
  }

  /// (I (x) a) C (I (x) a)^T / dt^2, a = R_c^T R_body, dense.
  Eigen::MatrixXd patch_block(const Eigen::MatrixXd& compliance) const {
    Eigen::Matrix3d rct;
    rct << 0, 0, 1, 1, 0, 0, 0, 1, 0;
    const int size = static_cast<int>(compliance.rows());
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(size, size);
    for (int k = 0; k < size / 3; ++k) {
      a.block<3, 3>(3 * k, 3 * k) = rct * rotation;
    }
    return a * compliance * a.transpose() / (dt * dt);
  }

  Eigen::MatrixXd random_compliance(int size) {
    std::normal_distribution<double> normal;
    Eigen::MatrixXd b(size, size);
    for (int i = 0; i < size; ++i) {
      for (int j = 0; j < size; ++j) {
        b(i, j) = normal(rng);
      }
    }
    const Eigen::MatrixXd c =
        1e-6 * (b * b.transpose() / size + Eigen::MatrixXd::Identity(size, size));
    return 0.5 * (c + c.transpose()); // exactly symmetric
  }

  const Model model;
  std::mt19937 rng;
  const double dt = 1e-3;
  PdGains gains = PdGains::Uniform(model, 1e4, 200.0);
  Eigen::VectorXd tau, q_ref, v_ref, v_free;
  std::vector<Candidate> candidates; // in the stepper's row order
  int patch_body = 0;
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::MatrixXd jc, g;
  Eigen::Matrix3d rotation;
};

TEST_F(ContactRows, RowsBlocksAndVelocityUpdateMatchDenseReference) {
  StepperParameters parameters;
  parameters.time_step = dt;
  parameters.contact_margin = std::numeric_limits<double>::infinity(); // every candidate
  Stepper stepper(model, parameters);
  stepper.set_gains(gains);
  Data data(model);

  // Standing pose, joints and velocities perturbed.
  Eigen::VectorXd q = model.neutral_configuration();
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int i = 2; i < model.n_bodies; ++i) {
    q[model.idx_q[i]] += 0.05 * uniform(rng);
  }
  forward_kinematics(model, data, q);
  const int right_sole = model.frame_id("r_sole"), left_sole = model.frame_id("l_sole");
  q[2] -= std::min(frame_placement(model, data, right_sole).translation.z(),
                   frame_placement(model, data, left_sole).translation.z());
  Eigen::VectorXd v = 0.1 * test::random_vector(model.nv, rng);
  tau = 5.0 * test::random_vector(model.nv, rng);
  q_ref = q;
  for (int i = 2; i < model.n_bodies; ++i) {
    q_ref[model.idx_q[i]] += 0.02 * uniform(rng);
  }
  v_ref = 0.1 * test::random_vector(model.nv, rng);

  // A 4 x 3 node patch under the right sole (dense random compliance), the left sole's
  // corners and two points on the right hand: three bodies.
  const Frame& right = model.frames[right_sole];
  patch_body = right.body;
  Eigen::Matrix3Xd nodes(3, 12);
  for (int ix = 0; ix < 4; ++ix) {
    for (int iy = 0; iy < 3; ++iy) {
      const Eigen::Vector3d sole_point(-0.1 + 0.2 * ix / 3.0, -0.06 + 0.06 * iy, 0.0);
      nodes.col(3 * ix + iy) = right.placement.act_point(sole_point);
      candidates.push_back({patch_body, nodes.col(3 * ix + iy)});
    }
  }
  Eigen::MatrixXd compliance = random_compliance(36);
  coupling::PadState pad(compliance);
  stepper.add_deformable_patch(patch_body, nodes, 0.8, pad);
  const Frame& left = model.frames[left_sole];
  for (const double x : {-0.1086, 0.1086}) {
    for (const double y : {-0.069, 0.069}) {
      const Eigen::Vector3d p = left.placement.act_point(Eigen::Vector3d(x, y, 0));
      stepper.add_contact_point(left.body, p, 0.8);
      candidates.push_back({left.body, p});
    }
  }
  const int hand = model.frames[model.frame_id("RARM_LINK6")].body;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.02, 0.01, -0.1), Eigen::Vector3d(-0.03, 0, 0.05)}) {
    stepper.add_contact_point(hand, p, 0.5);
    candidates.push_back({hand, p});
  }
  const int n = static_cast<int>(candidates.size());

  auto check_step = [&](const char* what, const Eigen::MatrixXd& c) {
    const Eigen::VectorXd q0 = q, v0 = v;
    const Eigen::VectorXd u_prev = pad.displacement();
    stepper.step(q, v, tau, q_ref, v_ref);
    reference(q0, v0);
    const contact::ContactProblem& problem = stepper.problem();
    ASSERT_EQ(problem.n_contacts, n);
    Eigen::VectorXd vc = jc * v_free;
    vc.head(36) -= u_prev / dt; // deformation-rate term of the patch (eq. 12)
    Eigen::VectorXd p(3 * n);
    for (int k = 0; k < 12; ++k) {
      p.segment<3>(3 * k) = stepper.node_impulse(0, k);
    }
    for (int k = 12; k < n; ++k) {
      p.segment<3>(3 * k) = stepper.point_impulse(k - 12);
    }
    const Eigen::VectorXd v_plus = v_free + llt.solve(jc.transpose() * p);
    const auto g_stepper = problem.rigid_factor.topRows(3 * n);
    const double e_g = relative_error(g_stepper * g_stepper.transpose(), g * g.transpose());
    const double e_vc = relative_error(problem.free_velocity.head(3 * n), vc);
    Eigen::MatrixXd w_stepper;
    problem.assemble_delassus(w_stepper);
    Eigen::MatrixXd w_reference = g * g.transpose();
    w_reference.topLeftCorner(36, 36) += patch_block(c);
    const double e_block = relative_error(w_stepper, w_reference);
    std::printf("rigid factor: %d columns for %d degrees of freedom\n",
                static_cast<int>(problem.rigid_factor.cols()), static_cast<int>(g.cols()));
    EXPECT_EQ(problem.rigid_factor.cols(), 18); // 6 per contact body (patch, left foot, hand)
    // The patch's factored rows (I (x) a) Lambda T (the direct solve's structure).
    const contact::CompliantPatch& patch = problem.patches[0];
    const contact::PatchLever& structure = problem.patch_levers[0];
    ASSERT_TRUE(structure.version > 0 && structure.lever_map_valid);
    const Eigen::MatrixXd factored = structure.lever * structure.lever_map;
    Eigen::MatrixXd factored_contact(36, factored.cols());
    for (int k = 0; k < 12; ++k) {
      factored_contact.middleRows<3>(3 * k) = patch.rotation * factored.middleRows<3>(3 * k);
    }
    const double e_lever = relative_error(factored_contact, g_stepper.topRows(36));
    std::printf("patch rows (I (x) a) Lambda T against G: %.2e (tol 1e-12)\n", e_lever);
    EXPECT_LT(e_lever, 1e-12);
    const double e_v = relative_error(v, v_plus);
    std::printf("%s: %d contacts, |p| = %.3e N s; relative errors G G^T %.2e, v_free,c %.2e, "
                "W %.2e, v+ %.2e (tol 1e-12)\n",
                what, n, p.norm(), e_g, e_vc, e_block, e_v);
    EXPECT_GT(p.norm(), 0.0); // the update is exercised
    EXPECT_LT(e_g, 1e-12);
    EXPECT_LT(e_vc, 1e-12);
    EXPECT_LT(e_block, 1e-12);
    EXPECT_LT(e_v, 1e-12);
  };
  check_step("first step", compliance);
  check_step("second step (deformation-rate term)", compliance);
  // Same start state again: the stepper keeps its blocks (same rotation, same C).
  const Eigen::VectorXd q1 = q, v1 = v;
  check_step("third step", compliance);
  q = q1;
  v = v1;
  check_step("repeated third step (blocks kept)", compliance);
  // A new compliance at the same rotation must be rotated again.
  q = q1;
  v = v1;
  compliance = random_compliance(36);
  pad.set_compliance(compliance, Eigen::VectorXd::Zero(36));
  check_step("repeated third step, new compliance", compliance);
}

} // namespace
} // namespace plantar::multibody
