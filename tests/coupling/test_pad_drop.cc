// A deformable pad (coupling/deformable_pad.h, issue 22) under a single free rigid body in the
// multibody stepper, against the closed-form spring-mass answer.
//
// The body is a uniform block (tests/coupling/foot_block_model.h, m = 10 kg, 0.1 x 0.1 x
// 0.05 m) with the knee pad of meshes/pad_knee.geo (0.08 x 0.08 x 0.015 m, Q1 hexahedra
// 8 x 8 x 2, 81 contact nodes, E = 1 MPa, nu = 0.3) centred under its CoM, turned by 90 deg
// about z on the link (a square pad: the same physics, but the link-frame rotation is used).
// The ground is frictionless (mu = 0). The pad is massless (static condensation) and the body
// stays level by symmetry, so every contact node moves down by the same amount with zero
// tangential force: the pad is exactly a linear spring of stiffness k = k_z = 1^T C_zz^-1 1
// (DeformablePad::vertical_stiffness) under the mass m. Released at rest with the pad touching
// the ground unloaded, the compression is x(t) = (m g / k) (1 - cos(w t)), w = sqrt(k / m):
// static deflection m g / k, peak 2 m g / k at t = pi sqrt(m / k). theta = 1/2 (the implicit
// midpoint rule) does not damp the linear spring; its discrete frequency is w (1 - (w dt)^2 /
// 12 + ...), so the errors are second order in dt (measured below).
#include "coupling/deformable_pad.h"
#include "coupling/pad_state.h"
#include "foot_block_model.h"
#include "multibody/model.h"
#include "multibody/stepper.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace plantar::coupling {
namespace {

using multibody::Model;
using multibody::Stepper;
using multibody::StepperParameters;

constexpr double mass = 10.0, g = 9.81;       // kg, m/s^2
constexpr double L = 0.1, W = 0.1, H = 0.05;  // body block, m
constexpr double pad_a = 0.08, pad_t = 0.015; // pad side and thickness, m
constexpr double E = 1e6, nu = 0.3;           // Pa, -
const double pi = std::acos(-1.0);

PadDescription knee_pad() {
  PadDescription d;
  d.name = "knee";
  d.geometry_file = std::filesystem::path(PLANTAR_SOURCE_DIR) / "meshes" / "pad_knee.geo";
  d.mesh_numbers = {{"PadLength", pad_a},
                    {"PadWidth", pad_a},
                    {"PadThickness", pad_t},
                    {"PadMeshSize", 0.01},
                    {"PadHex", 1}};
  d.cache_directory = std::filesystem::current_path() / "mesh-cache";
  d.materials = "pad: E=1e6, nu=0.3";
  d.degree = 1;
  d.link = "foot";
  d.translation = Eigen::Vector3d(0, 0, -H / 2); // the block's bottom face, under the CoM
  d.rpy = Eigen::Vector3d(0, 0, pi / 2);
  d.friction = 0.0;
  return d;
}

/// Attaches @p pad to the body of its link with its state @p state (its compliance), with
/// Kelvin-Voigt damping time @p damping (s) if positive.
void attach_pad(Stepper& stepper, const Model& model, const DeformablePad& pad, PadState& state,
                double damping) {
  stepper.add_deformable_patch(model.body_id(pad.link()), pad.contact_positions(), pad.friction(),
                               state);
  if (damping > 0)
    state.set_damping(damping);
}

struct Trace {
  std::vector<double> compression; // z0 - z after each step, m (index i: t = (i + 1) dt)
  double final_speed = 0, max_tilt = 0, max_drift = 0;
  int unconverged = 0;
};

/// Releases the body at rest with the pad's lowest node at height @p drop (m) and steps for
/// @p duration (s).
Trace simulate(const Model& model, const DeformablePad& pad, double dt, double duration,
               double drop, double damping) {
  StepperParameters parameters;
  parameters.time_step = dt;
  parameters.theta = 0.5;
  // Frictionless: Gauss-Seidel converges (ADMM with its defaults left 75 to 837 of the solves
  // of a run above its tolerance, and took 100 times longer).
  parameters.solver.solver = contact::ContactSolverType::gauss_seidel;
  parameters.max_contacts = pad.n_contacts() + 4;
  PadState state(pad.compliance());
  Stepper stepper(model, parameters);
  attach_pad(stepper, model, pad, state, damping);
  const double z0 = drop - pad.contact_positions().row(2).minCoeff();
  Eigen::VectorXd q(7), v = Eigen::VectorXd::Zero(6);
  q << 0, 0, z0, 0, 0, 0, 1;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  Trace run;
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int i = 0; i < steps; ++i) {
    const multibody::StepReport report = stepper.step(q, v, zero, q, zero);
    run.unconverged += !report.solver.converged();
    run.compression.push_back(z0 - drop - q[2]);
    run.max_tilt = std::max(run.max_tilt, 2 * Eigen::Vector3d(q[3], q[4], q[5]).norm());
    run.max_drift = std::max(run.max_drift, q.head<2>().norm());
  }
  run.final_speed = v.norm();
  return run;
}

/// The first local maximum of @p x (samples at t_i = (i + 1) dt), refined by the parabola
/// through it and its neighbours: {time s, value m}.
std::pair<double, double> first_peak(const std::vector<double>& x, double dt) {
  for (std::size_t i = 1; i + 1 < x.size(); ++i)
    if (x[i] >= x[i - 1] && x[i] > x[i + 1]) {
      const double curvature = x[i - 1] - 2 * x[i] + x[i + 1];
      const double s = 0.5 * (x[i - 1] - x[i + 1]) / curvature; // offset in steps
      return {(i + 1 + s) * dt, x[i] - 0.25 * (x[i - 1] - x[i + 1]) * s};
    }
  return {NAN, NAN};
}

class PadDrop : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    model_ = std::make_unique<Model>(::plantar::test::foot_block_model(mass, L, W, H));
    pad_ = std::make_unique<DeformablePad>(knee_pad());
  }
  static std::unique_ptr<Model> model_;
  static std::unique_ptr<DeformablePad> pad_;
};
std::unique_ptr<Model> PadDrop::model_;
std::unique_ptr<DeformablePad> PadDrop::pad_;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no std::invalid_argument)";
}

TEST(PadDescriptionTest, EveryInputIsValidated) {
  struct Case {
    std::function<void(PadDescription&)> change;
    std::vector<std::string> expected; // substrings of the message
  };
  const std::vector<Case> cases = {
      {[](PadDescription& d) { d.name = ""; }, {"name is empty"}},
      {[](PadDescription& d) { d.geometry_file = ""; }, {"knee", "geometry_file is empty"}},
      {[](PadDescription& d) { d.geometry_file = "meshes/no_such_pad.geo"; },
       {"geometry_file = 'meshes/no_such_pad.geo'", "no such file"}},
      {[](PadDescription& d) { d.mesh_numbers["PadThickness"] = NAN; },
       {"mesh_numbers[PadThickness] = nan", "finite"}},
      {[](PadDescription& d) { d.mesh_numbers[""] = 1; }, {"empty gmsh parameter name"}},
      {[](PadDescription& d) { d.gmsh_executable = ""; }, {"gmsh_executable is empty"}},
      {[](PadDescription& d) { d.materials = " ; "; }, {"materials = ' ; '", "no region"}},
      {[](PadDescription& d) { d.degree = 3; }, {"degree = 3", "1 or 2"}},
      {[](PadDescription& d) { d.link = ""; }, {"link is empty"}},
      {[](PadDescription& d) { d.translation.y() = INFINITY; },
       {"translation = (0, inf, -0.025", "finite"}},
      {[](PadDescription& d) { d.rpy.x() = NAN; }, {"rpy = (nan, 0, ", "finite"}},
      {[](PadDescription& d) { d.friction = -0.1; }, {"friction = -0.1", "[0, 100]"}},
      {[](PadDescription& d) { d.friction = NAN; }, {"friction = nan", "[0, 100]"}},
  };
  for (const Case& c : cases) {
    PadDescription d = knee_pad();
    c.change(d);
    const std::string message = error_of([&] { DeformablePad pad(d); });
    for (const std::string& part : c.expected)
      EXPECT_NE(message.find(part), std::string::npos) << message << "\n  expected: " << part;
  }
  // Materials are resolved against the mesh's volumes ("pad" in meshes/pad_knee.geo) and parsed
  // by fem::parse_material_specs: the messages name the pad's parameter and the region.
  PadDescription d = knee_pad();
  d.materials = "rubber: E=1e6, nu=0.3";
  std::string message = error_of([&] { DeformablePad pad(d); });
  EXPECT_NE(message.find("rubber"), std::string::npos) << message;
  d.materials = "pad: E=abc, nu=0.3";
  message = error_of([&] { DeformablePad pad(d); });
  EXPECT_NE(message.find("pad 'knee' materials"), std::string::npos) << message;
  d.materials = "pad: E=-1, nu=0.3";
  message = error_of([&] { DeformablePad pad(d); });
  EXPECT_NE(message.find("-1"), std::string::npos) << message;
}

TEST_F(PadDrop, LinkFramePlacementIsRCRt) {
  // A general placement: positions t + R p, compliance blockwise R C R^T, against dense
  // products; k_z is a property of the pad (pad frame) and does not depend on it.
  PadDescription d = knee_pad();
  d.translation = Eigen::Vector3d(0.01, -0.02, 0.03);
  d.rpy = Eigen::Vector3d(0.3, -0.7, 2.1);
  const DeformablePad pad(d);
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(2.1, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  EXPECT_LT((pad.rotation() - r).cwiseAbs().maxCoeff(), 1e-15);
  const int n = pad.n_contacts();
  ASSERT_EQ(n, 81);
  const Eigen::MatrixXd& c = pad.condensed().compliance();
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int k = 0; k < n; ++k)
    t.block<3, 3>(3 * k, 3 * k) = r;
  const Eigen::MatrixXd expected = t * c * t.transpose();
  const double error =
      (pad.compliance() - expected).cwiseAbs().maxCoeff() / c.cwiseAbs().maxCoeff();
  const Eigen::Matrix3Xd positions =
      (r * pad.condensed().contact_positions().transpose()).colwise() + d.translation;
  const double position_error = (pad.contact_positions() - positions).cwiseAbs().maxCoeff();
  std::printf("link frame: compliance error %.2e (relative), positions %.2e m; k_z %.6e vs "
              "%.6e N/m\n",
              error, position_error, pad.vertical_stiffness(), pad_->vertical_stiffness());
  EXPECT_LT(error, 1e-14);
  EXPECT_LT(position_error, 1e-15);
  EXPECT_NEAR(pad.vertical_stiffness() / pad_->vertical_stiffness(), 1.0, 1e-14);
  EXPECT_NEAR(pad.thickness(), pad_t, 1e-15);
}

TEST_F(PadDrop, VerticalStiffnessBetweenTheLayerBounds) {
  // Independent estimates for a layer of area A and thickness t bonded on top, pushed by a
  // frictionless rigid plate: the uniaxial stress field bounds the exact stiffness from below,
  // E A / t, and the oedometric field (u_z linear in z, u_x = u_y = 0; it lies in the Q1 space)
  // bounds the FEM stiffness from above, E_oed A / t, E_oed = E (1-nu) / ((1+nu)(1-2nu)). The
  // displacement FEM is stiffer than the exact solution, so E A / t < k_z < E_oed A / t
  // (a factor (1+nu)(1-2nu)/(1-nu) = 0.743 apart at nu = 0.3).
  const double area = pad_a * pad_a;
  const double lower = E * area / pad_t;
  const double e_oed = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  const double upper = e_oed * area / pad_t;
  const double k = pad_->vertical_stiffness();
  std::printf("k_z = %.6e N/m = %.4f E A / t = %.4f E_oed A / t (E A / t = %.6e, E_oed A / t = "
              "%.6e N/m), %d contact nodes, thickness %.4f m\n",
              k, k / lower, k / upper, lower, upper, pad_->n_contacts(), pad_->thickness());
  EXPECT_GT(k, lower);
  EXPECT_LT(k, upper);
  // Linear elasticity: k_z proportional to E.
  PadDescription d = knee_pad();
  d.materials = "pad: E=4e6, nu=0.3";
  EXPECT_NEAR(DeformablePad(d).vertical_stiffness() / (4 * k), 1.0, 1e-12);
}

TEST_F(PadDrop, ReleasedAtRestOscillatesAsTheSpringMass) {
  const double k = pad_->vertical_stiffness();
  const double w = std::sqrt(k / mass), delta = mass * g / k, half = pi / w;
  std::printf("closed form: k = %.6e N/m, m g / k = %.6e m, 2 m g / k = %.6e m, pi sqrt(m/k) = "
              "%.6e s\n",
              k, delta, 2 * delta, half);
  std::printf("| dt (s) | w dt | peak (m) | peak error | half period (s) | error | trough (m) | "
              "(peak + trough) / 2 (m) | error | tilt (rad) |\n");
  for (const double dt : {2e-4, 1e-4, 5e-5}) {
    // Through the first trough (x = 0 again at t = 2 pi / w): the mean of the oscillation,
    // (peak + trough) / 2, is the static deflection.
    const Trace run = simulate(*model_, *pad_, dt, 2.2 * half, 0.0, 0.0);
    const auto [t_peak, peak] = first_peak(run.compression, dt);
    std::vector<double> negated;
    for (const double x : run.compression)
      negated.push_back(-x);
    const double trough =
        -first_peak(std::vector<double>(negated.begin() + std::lround(t_peak / dt), negated.end()),
                    dt)
             .second;
    const double mean = 0.5 * (peak + trough);
    const double peak_error = peak / (2 * delta) - 1, half_error = t_peak / half - 1,
                 mean_error = mean / delta - 1;
    std::printf("| %.0e | %.4f | %.6e | %+.2e | %.6e | %+.2e | %+.1e | %.6e | %+.2e | %.1e |\n", dt,
                w * dt, peak, peak_error, t_peak, half_error, trough, mean, mean_error,
                run.max_tilt);
    SCOPED_TRACE("dt = " + std::to_string(dt));
    EXPECT_EQ(run.unconverged, 0);
    EXPECT_LT(run.max_tilt, 1e-8);
    EXPECT_LT(run.max_drift, 1e-10);
    // Amplitude: the midpoint rule conserves the spring's energy, the peak is only sampled
    // (parabola through three samples): measured 3.5e-8, 4.6e-10, 8.0e-11 at dt 200, 100,
    // 50 us. Half period: the discrete frequency's phase lag (w dt)^2 / 12 (second order;
    // measured +1.70e-4, +4.24e-5, +1.06e-5 = that lag to 1 %). Mean: 2.5e-8, 1.4e-9, 1.0e-12.
    EXPECT_NEAR(peak_error, 0.0, 1e-6);
    EXPECT_GT(half_error, 0.0);
    EXPECT_NEAR(half_error / (w * w * dt * dt / 12), 1.0, 0.05);
    EXPECT_NEAR(mean_error, 0.0, 1e-6);
  }
}

TEST_F(PadDrop, DroppedFromOneMillimetre) {
  // Free fall from h = 1 mm, then the spring: peak compression
  // x_max = (m g / k) (1 + sqrt(1 + 2 k h / (m g))). The landing falls inside a step (the
  // patch enters the step that reaches the ground): first-order error in dt, measured below.
  const double k = pad_->vertical_stiffness(), delta = mass * g / k, h = 1e-3;
  const double expected = delta * (1 + std::sqrt(1 + 2 * h / delta));
  std::printf("| dt (s) | peak (m) | closed form (m) | error |\n");
  std::vector<double> errors;
  for (const double dt : {2e-4, 1e-4, 5e-5}) {
    const double duration = std::sqrt(2 * h / g) + std::acos(-1.0) * std::sqrt(mass / k);
    const Trace run = simulate(*model_, *pad_, dt, duration, h, 0.0);
    const double peak = first_peak(run.compression, dt).second;
    errors.push_back(peak / expected - 1);
    std::printf("| %.0e | %.6e | %.6e | %+.2e |\n", dt, peak, expected, errors.back());
    SCOPED_TRACE("dt = " + std::to_string(dt));
    EXPECT_EQ(run.unconverged, 0);
    EXPECT_LT(run.max_tilt, 1e-8);
  }
  // Measured -1.71e-4, -3.03e-5, -1.10e-5 at dt 200, 100, 50 us (where the landing falls in
  // its step varies with dt, so the order is irregular): 3e-4 at every dt, 2e-5 at the finest.
  for (const double error : errors)
    EXPECT_LT(std::abs(error), 3e-4);
  EXPECT_LT(std::abs(errors.back()), 2e-5);
}

TEST_F(PadDrop, DampedPadSettlesAtTheStaticDeflection) {
  // Kelvin-Voigt damping time 2 ms (damping ratio beta w / 2 = 0.2): the pad settles at
  // m g / k_z whatever dt.
  const double k = pad_->vertical_stiffness(), delta = mass * g / k;
  for (const double dt : {1e-3, 2e-4}) {
    const Trace run = simulate(*model_, *pad_, dt, 0.4, 0.0, 2e-3);
    const double sink = run.compression.back();
    std::printf("damped, dt = %.0e s: static deflection %.8e m vs m g / k = %.8e m (%+.2e), "
                "final |v| %.1e m/s\n",
                dt, sink, delta, sink / delta - 1, run.final_speed);
    SCOPED_TRACE("dt = " + std::to_string(dt));
    EXPECT_EQ(run.unconverged, 0);
    // Measured -1.6e-9 and -1.4e-9 (the solver's tolerance): 1e-6.
    EXPECT_NEAR(sink / delta, 1.0, 1e-6);
    EXPECT_LT(run.final_speed, 1e-6);
  }
}

} // namespace
} // namespace plantar::coupling
