// A condensed pad (coupling/deformable_pad.h: the knee pad of meshes/pad_knee.geo, 0.08 x 0.08
// x 0.015 m, Q1 8 x 8 x 2, 81 contact nodes, E = 1 MPa, nu = 0.3) under a free 10 kg block,
// pressed onto uneven ground (contact/terrain.h), issue 23:
//  - onto a cylindrical bump (radius 0.3 m, 3 mm high, axis along y under the pad's centre: the
//    node frames tilt by up to 8 deg): force balance, gap complementarity at every node, and the
//    nodal displacements equal to a direct FEM solve (UMFPACK) of the pad loaded by the contact
//    forces found;
//  - half over a step edge (5 mm high, sharp, 2.5 cm left of the centre): the nodes over the
//    lower level carry nothing, and every force, the centre of pressure and the pose equal
//    those of the same pad cut to its nodes over the upper level (the compliance's sub-block:
//    exact when the others carry no force) on flat ground at the upper level.
#include "contact/cylinder_terrain.h"
#include "contact/flat_terrain.h"
#include "contact/step_terrain.h"
#include "coupling/deformable_pad.h"
#include "coupling/pad_state.h"
#include "fem/linear_solver.h"
#include "foot_block_model.h"
#include "multibody/kinematics.h"
#include "multibody/stepper.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

namespace plantar::coupling {
namespace {

using multibody::Model;
using multibody::Stepper;
using multibody::StepperParameters;

constexpr double mass = 10.0, g = 9.81, push = 150.0; // kg, m/s^2, N (down, on the CoM)
constexpr double H = 0.05;                            // block height, m

PadDescription knee_pad() {
  PadDescription d;
  d.name = "knee";
  d.geometry_file = std::filesystem::path(PLANTAR_SOURCE_DIR) / "meshes" / "pad_knee.geo";
  d.mesh_numbers = {{"PadLength", 0.08},
                    {"PadWidth", 0.08},
                    {"PadThickness", 0.015},
                    {"PadMeshSize", 0.01},
                    {"PadHex", 1}};
  d.cache_directory = std::filesystem::current_path() / "mesh-cache";
  d.materials = "pad: E=1e6, nu=0.3";
  d.degree = 1;
  d.link = "foot";
  d.translation = Eigen::Vector3d(0, 0, -H / 2);
  d.friction = 0.8;
  return d;
}

struct Settled {
  Eigen::VectorXd q;
  double speed = 0;
  Eigen::Matrix3Xd force;        // per node, world, N (end of the last step)
  Eigen::Matrix3Xd displacement; // per node, world, m
  Eigen::Matrix3Xd position;     // per node, world, undeformed, m
  Eigen::Matrix3d rotation;      // R_body
  int unconverged = 0;
};

/// The block with a pad of @p nodes (link frame) and @p compliance (link frame) on @p terrain,
/// released 0.1 mm above the highest ground under its nodes at (0, 0), pushed down by `push`,
/// stepped for 3 s (dt 1 ms, theta 1, pad damping 2 ms).
Settled settle(const Model& model, const Eigen::Matrix3Xd& nodes, const Eigen::MatrixXd& compliance,
               const contact::Terrain& terrain) {
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  parameters.solver.tolerance = 1e-10;
  parameters.solver.max_iterations = 20000;
  parameters.max_contacts = static_cast<int>(nodes.cols());
  PadState state(compliance);
  Stepper stepper(model, parameters, terrain);
  stepper.add_deformable_patch(1, nodes, 0.8, state);
  state.set_damping(2e-3);
  double z = -1e9;
  for (int k = 0; k < nodes.cols(); ++k)
    z = std::max(z, terrain.height(nodes(0, k), nodes(1, k)) - nodes(2, k));
  Eigen::VectorXd q(7), v = Eigen::VectorXd::Zero(6);
  q << 0, 0, z + 1e-4, 0, 0, 0, 1;
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(6);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  Settled out;
  for (int n = 0; n < 3000; ++n) {
    const Eigen::Matrix3d r = Eigen::Quaterniond(q[6], q[3], q[4], q[5]).toRotationMatrix();
    tau.head<3>() = r.transpose() * Eigen::Vector3d(0, 0, -push);
    out.unconverged += !stepper.step(q, v, tau, q, zero).solver.converged();
  }
  multibody::Data data(model);
  multibody::forward_kinematics(model, data, q);
  out.q = q;
  out.speed = v.norm();
  out.rotation = data.oMi[1].rotation;
  const int n = static_cast<int>(nodes.cols());
  out.force.resize(3, n);
  out.displacement.resize(3, n);
  out.position.resize(3, n);
  for (int k = 0; k < n; ++k) {
    out.force.col(k) = state.node_to_world(k, state.node_force(k));
    out.displacement.col(k) = state.node_to_world(k, state.displacement().segment<3>(3 * k));
    out.position.col(k) = data.oMi[1].act_point(nodes.col(k));
  }
  return out;
}

class PadTerrain : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    model_ = std::make_unique<Model>(::plantar::test::foot_block_model(mass, 0.1, 0.1, H));
    pad_ = std::make_unique<DeformablePad>(knee_pad());
  }
  static std::unique_ptr<Model> model_;
  static std::unique_ptr<DeformablePad> pad_;
};
std::unique_ptr<Model> PadTerrain::model_;
std::unique_ptr<DeformablePad> PadTerrain::pad_;

TEST_F(PadTerrain, PressedOntoACylindricalBump) {
  const contact::CylinderTerrain bump(0.3, 0.003, M_PI / 2, Eigen::Vector2d::Zero(), 0.0);
  const Settled s = settle(*model_, pad_->contact_positions(), pad_->compliance(), bump);
  const int n = pad_->n_contacts();
  const double load = mass * g + push;
  // Force balance: the node forces carry the weight and the push.
  const Eigen::Vector3d total = s.force.rowwise().sum();
  // Complementarity per node, with the deformed node's first-order gap on the terrain and its
  // normal force (contact frame).
  double min_gap = 1e9, max_loaded_gap = 0, max_free_force = 0, min_normal = 1e9, max_tilt = 0;
  int n_loaded = 0;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d deformed = s.position.col(k) + s.displacement.col(k);
    const contact::TerrainContact ground = contact::terrain_contact(bump, deformed);
    const double f_n = ground.frame.col(0).dot(s.force.col(k));
    min_gap = std::min(min_gap, ground.gap);
    min_normal = std::min(min_normal, f_n);
    max_tilt = std::max(max_tilt, std::acos(ground.frame(2, 0)));
    if (f_n > 1e-6 * load) {
      ++n_loaded;
      max_loaded_gap = std::max(max_loaded_gap, std::abs(ground.gap));
    } else {
      max_free_force = std::max(max_free_force, std::abs(f_n));
    }
  }
  // The direct FEM solve: the forces (pad frame = link frame here) as nodal loads.
  const CondensedSole& sole = pad_->condensed();
  dealii::Vector<double> rhs(sole.n_dofs()), full(sole.n_dofs());
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d f = s.rotation.transpose() * s.force.col(k);
    for (int d = 0; d < 3; ++d)
      rhs(sole.contact_dofs()[k][d]) = f[d];
  }
  fem::LinearSolver umfpack{fem::LinearSolverSettings{}};
  umfpack.initialize(sole.elasticity().stiffness_matrix());
  umfpack.solve(rhs, full);
  sole.elasticity().constraints().distribute(full);
  double u_error = 0, u_max = 0;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d u = s.rotation.transpose() * s.displacement.col(k);
    const Eigen::Vector3d u_fem(full(sole.contact_dofs()[k][0]), full(sole.contact_dofs()[k][1]),
                                full(sole.contact_dofs()[k][2]));
    u_error = std::max(u_error, (u - u_fem).norm());
    u_max = std::max(u_max, u_fem.norm());
  }
  std::printf("pad on a cylindrical bump: %d of %d nodes loaded, node frames tilted up to %.2f "
              "deg; sum of forces (%.2e, %.2e, %.6f) N vs (0, 0, %.6f) N; min gap %.2e m, max "
              "|gap| of a loaded node %.2e m, max |f_n| of a free node %.2e N, min f_n %.2e N; "
              "|U - U_FEM| %.2e m of max |U| %.2e m; |v| %.1e m/s, unconverged %d\n",
              n_loaded, n, max_tilt * 180 / M_PI, total.x(), total.y(), total.z(), load, min_gap,
              max_loaded_gap, max_free_force, min_normal, u_error, u_max, s.speed, s.unconverged);
  // A genuinely uneven contact: some nodes loaded, some free, frames tilted.
  EXPECT_GT(n_loaded, 9);
  EXPECT_LT(n_loaded, n);
  EXPECT_GT(max_tilt, 2 * M_PI / 180);
  // Force balance to the settling and solver tolerance (|v| ~ 0: m |dv|/dt ~ 1e-6 N).
  EXPECT_NEAR(total.z(), load, 1e-6 * load);
  EXPECT_LT(std::hypot(total.x(), total.y()), 1e-6 * load);
  // Complementarity: tolerances from the solver (1e-10 m/s x 1 ms) and the first-order gap of
  // the deformed node (|u|^2 kappa ~ (1e-3)^2 / 0.3 ~ 3e-6 m, and the node's tangential
  // displacement times the slope); the stepper uses gap(x) + U_n, this test gap(x + u).
  EXPECT_GT(min_gap, -5e-6);
  EXPECT_LT(max_loaded_gap, 5e-6);
  EXPECT_GE(min_normal, -1e-9 * load);
  EXPECT_LT(max_free_force, 1e-6 * load);
  // U = C F against the full FEM field: condensation exactness (1e-10) and the damped
  // relaxation left after 3 s.
  EXPECT_LT(u_error, 1e-6 * u_max);
  EXPECT_LT(s.speed, 1e-5);
  EXPECT_EQ(s.unconverged, 0);
}

TEST_F(PadTerrain, HalfOverAStepEdge) {
  const double rise = 0.005, edge = -0.025;
  const contact::StepTerrain step(rise, 0.0, Eigen::Vector2d(edge, 0.0), 0.0, 0.0);
  const Eigen::Matrix3Xd& nodes = pad_->contact_positions();
  const Settled s = settle(*model_, nodes, pad_->compliance(), step);
  // The reference: the nodes over the upper level only (x > edge), the compliance's sub-block,
  // flat ground at the upper level.
  std::vector<int> upper;
  for (int k = 0; k < nodes.cols(); ++k)
    if (nodes(0, k) > edge)
      upper.push_back(k);
  const int n_upper = static_cast<int>(upper.size());
  Eigen::Matrix3Xd cut(3, n_upper);
  Eigen::MatrixXd cut_compliance(3 * n_upper, 3 * n_upper);
  for (int i = 0; i < n_upper; ++i) {
    cut.col(i) = nodes.col(upper[i]);
    for (int j = 0; j < n_upper; ++j)
      cut_compliance.block<3, 3>(3 * i, 3 * j) =
          pad_->compliance().block<3, 3>(3 * upper[i], 3 * upper[j]);
  }
  const contact::FlatTerrain upper_level(rise);
  const Settled r = settle(*model_, cut, cut_compliance, upper_level);
  const double load = mass * g + push;
  double lower_force = 0, force_difference = 0;
  std::vector<char> is_upper(nodes.cols(), 0);
  for (int i = 0; i < n_upper; ++i) {
    is_upper[upper[i]] = 1;
    force_difference = std::max(force_difference, (s.force.col(upper[i]) - r.force.col(i)).norm());
  }
  for (int k = 0; k < nodes.cols(); ++k)
    if (!is_upper[k])
      lower_force = std::max(lower_force, s.force.col(k).norm());
  auto pressure_centre = [](const Settled& run) {
    const Eigen::Vector3d total = run.force.rowwise().sum();
    return (run.position.row(0).dot(run.force.row(2)) / total.z());
  };
  const double cop = pressure_centre(s), cop_reference = pressure_centre(r);
  const Eigen::Vector3d total = s.force.rowwise().sum();
  std::printf("pad half over a step edge: %d of %ld nodes over the upper level; max |F| of a "
              "node over the lower level %.2e N; sum F_z %.6f N (load %.6f); CoP x %.6f m "
              "(edge at %.3f; cut pad on flat ground %.6f m); max node force difference %.2e N; "
              "pose difference %.2e; |v| %.1e m/s\n",
              n_upper, static_cast<long>(nodes.cols()), lower_force, total.z(), load, cop, edge,
              cop_reference, force_difference, (s.q - r.q).cwiseAbs().maxCoeff(), s.speed);
  EXPECT_LT(lower_force, 1e-9 * load);
  EXPECT_NEAR(total.z(), load, 1e-6 * load);
  EXPECT_GT(cop, edge);
  EXPECT_NEAR(cop, cop_reference, 1e-7);
  EXPECT_LT(force_difference, 1e-6 * load);
  EXPECT_LT((s.q - r.q).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_EQ(s.unconverged, 0);
  EXPECT_EQ(r.unconverged, 0);
}

} // namespace
} // namespace plantar::coupling
