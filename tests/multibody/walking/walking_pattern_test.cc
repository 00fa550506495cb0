// The walk of David et al. 2008 (six steps in six seconds), the standing and lean references:
// ZMP inside the support polygon, swing feet landing at rest on their footsteps, a continuous
// joint reference within the URDF limits that realises the planned sole poses.
#include "multibody/walking/leg_ik.h"
#include "multibody/walking/walking_reference.h"
#include "tests/multibody/walking/hrp2_humanoid.h"
#include "tests/multibody/walking/urdf_fk.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <stdexcept>
#include <urdf_parser/urdf_parser.h>

namespace {

using namespace plantar::walking;
using plantar::walking::testing::hrp2_description;
using plantar::walking::testing::hrp2_model;
using plantar::walking::testing::hrp2_urdf;
using plantar::walking::testing::link_pose;
using plantar::walking::testing::mass_and_com;

const Footstep kRightSole{0.0, -0.105, 0.0}, kLeftSole{0.0, 0.105, 0.0}; // feet side by side
constexpr double kFootLength = 0.2172, kFootWidth = 0.138;               // public HRP-2 sole size

using Point = Eigen::Vector2d;

double cross(const Point& o, const Point& a, const Point& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Convex hull (Andrew's monotone chain), counter-clockwise.
std::vector<Point> convex_hull(std::vector<Point> points) {
  std::sort(points.begin(), points.end(), [](const Point& a, const Point& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Point> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0)
      --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], points[i - 1]) <= 0)
      --k;
    hull[k++] = points[i - 1];
  }
  hull.resize(k - 1);
  return hull;
}

/// Signed distance from p to the boundary of a convex CCW polygon (> 0 inside).
double inside_margin(const std::vector<Point>& polygon, const Point& p) {
  double margin = 1e9;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Point& a = polygon[i];
    const Point& b = polygon[(i + 1) % polygon.size()];
    margin = std::min(margin, cross(a, b, p) / (b - a).norm());
  }
  return margin;
}

void add_sole_corners(std::vector<Point>& points, const Eigen::Vector3d& centre, double yaw) {
  const Eigen::Rotation2Dd rotation(yaw);
  for (double sx : {-0.5, 0.5})
    for (double sy : {-0.5, 0.5})
      points.push_back(centre.head<2>() + rotation * Point(sx * kFootLength, sy * kFootWidth));
}

/// Joint angles of sample k of the reference, by the reference's own column names.
std::map<std::string, double> named_angles(const JointReference& ref, int k) {
  std::map<std::string, double> named;
  for (int i = 0; i < ref.q.cols(); ++i)
    named[ref.joint_names[i]] = ref.q(k, i);
  return named;
}

urdf::ModelInterfaceSharedPtr parse_hrp2() {
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(hrp2_urdf());
  if (!model)
    throw std::runtime_error("urdfdom failed to parse " + hrp2_urdf());
  return model;
}

Eigen::Isometry3d base_pose(const JointReference& ref, int k) {
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = ref.base_position.row(k).transpose();
  base.linear() = Eigen::Quaterniond(ref.base_orientation(k, 0), ref.base_orientation(k, 1),
                                     ref.base_orientation(k, 2), ref.base_orientation(k, 3))
                      .toRotationMatrix();
  return base;
}

/// Max joint-limit violation (rad, <= 0 means inside) and max |dq/dt| / velocity limit.
void check_limits(const urdf::ModelInterface& model, const JointReference& ref,
                  double& worst_violation, double& worst_speed_ratio, std::string& worst_joint) {
  worst_violation = -1e9;
  worst_speed_ratio = 0.0;
  for (int j = 0; j < ref.q.cols(); ++j) {
    const auto limits = model.getJoint(ref.joint_names[j])->limits;
    const Eigen::VectorXd column = ref.q.col(j);
    const double violation =
        std::max(column.maxCoeff() - limits->upper, limits->lower - column.minCoeff());
    if (violation > worst_violation) {
      worst_violation = violation;
      worst_joint = ref.joint_names[j];
    }
    for (int k = 0; k + 1 < ref.n_samples(); ++k)
      worst_speed_ratio = std::max(worst_speed_ratio, std::abs(column(k + 1) - column(k)) /
                                                          ref.period / limits->velocity);
  }
}

class WalkingPatternTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    urdf_ = parse_hrp2();
    model_ = new plantar::multibody::Model(hrp2_model());
    humanoid_ = new Humanoid(*model_, hrp2_description());
    pattern_ = new WalkingPattern(make_walking_pattern(*model_, *humanoid_, WalkingParameters()));
  }
  static void TearDownTestSuite() {
    delete pattern_;
    delete humanoid_;
    delete model_;
  }
  static urdf::ModelInterfaceSharedPtr urdf_; ///< the independent oracle (urdf_fk.h)
  static plantar::multibody::Model* model_;
  static Humanoid* humanoid_;
  static WalkingPattern* pattern_;
};
urdf::ModelInterfaceSharedPtr WalkingPatternTest::urdf_;
plantar::multibody::Model* WalkingPatternTest::model_ = nullptr;
Humanoid* WalkingPatternTest::humanoid_ = nullptr;
WalkingPattern* WalkingPatternTest::pattern_ = nullptr;

TEST_F(WalkingPatternTest, PaperWalkTimingAndSteps) {
  const WalkingParameters walk;
  const FootstepPlan& plan = pattern_->plan;
  double max_travel = 0.0;
  Footstep right = walk.initial_right, left = walk.initial_left;
  for (size_t i = 0; i < walk.footsteps.size(); ++i) {
    Footstep& swing = i % 2 == 0 ? right : left;
    max_travel = std::max(max_travel,
                          std::hypot(walk.footsteps[i].x - swing.x, walk.footsteps[i].y - swing.y));
    swing = walk.footsteps[i];
  }
  std::printf("walk: %zu steps, %.3f s (paper: 6 steps in 6 s), longest step %.3f m (paper <= "
              "0.45), whole reference %.3f s, %d samples\n",
              walk.footsteps.size(), plan.walk_end - plan.walk_start, max_travel,
              pattern_->reference.duration(), plan.n_samples);
  EXPECT_EQ(walk.footsteps.size(), 6u);
  EXPECT_NEAR(plan.walk_end - plan.walk_start, 6.0, 1e-12);
  EXPECT_LE(max_travel, 0.45 + 1e-12);
  // A step longer than max_step_length is rejected.
  WalkingParameters too_long = walk;
  too_long.footsteps[2].x = too_long.footsteps[0].x + 0.46;
  EXPECT_THROW(make_footstep_plan(too_long), std::invalid_argument);
}

TEST_F(WalkingPatternTest, ZmpInsideSupportPolygon) {
  const FootstepPlan& plan = pattern_->plan;
  const PreviewControlParameters preview; // g, z_c = 0.814 as used by make_walking_pattern
  double min_margin = 1e9, min_margin_time = 0.0, max_ref_error = 0.0;
  double min_margin_single = 1e9;
  for (int k = 0; k < plan.n_samples; ++k) {
    // Cart-table ZMP recomputed here from the CoM states: p = c - z_c / g c''.
    const Point zmp(
        pattern_->com_x(k, 0) - preview.com_height / preview.gravity * pattern_->com_x(k, 2),
        pattern_->com_y(k, 0) - preview.com_height / preview.gravity * pattern_->com_y(k, 2));
    max_ref_error = std::max(max_ref_error, (zmp - plan.zmp_reference.row(k).transpose()).norm());
    std::vector<Point> corners;
    if (plan.phase[k] != SupportPhase::left_support)
      add_sole_corners(corners, plan.right_sole.row(k).transpose(), plan.right_yaw(k));
    if (plan.phase[k] != SupportPhase::right_support)
      add_sole_corners(corners, plan.left_sole.row(k).transpose(), plan.left_yaw(k));
    const double margin = inside_margin(convex_hull(corners), zmp);
    if (margin < min_margin) {
      min_margin = margin;
      min_margin_time = plan.time(k);
    }
    if (plan.phase[k] != SupportPhase::double_support)
      min_margin_single = std::min(min_margin_single, margin);
  }
  std::printf("cart-table ZMP: min margin to the support polygon %.4f m at t = %.3f s (tol >= "
              "0.02 m), in single support %.4f m; max |p - p_ref| %.4f m\n",
              min_margin, min_margin_time, min_margin_single, max_ref_error);
  EXPECT_GT(min_margin, 0.02);
  // The whole-body CoM of q_ref, recomposed by the test's own URDF chain (urdf_fk.h), equals
  // the preview-control CoM, and the reference's CoM column.
  const JointReference& ref = pattern_->reference;
  ASSERT_EQ(ref.n_samples(), plan.n_samples);
  double com_error = 0.0, com_column_error = 0.0;
  for (int k = 0; k < plan.n_samples; ++k) {
    const Eigen::Vector3d com =
        base_pose(ref, k) * mass_and_com(*urdf_, named_angles(ref, k)).second;
    com_error = std::max(
        com_error, std::hypot(com.x() - pattern_->com_x(k, 0), com.y() - pattern_->com_y(k, 0)));
    com_column_error = std::max(com_column_error, (com - ref.com.row(k).transpose()).norm());
  }
  const Eigen::VectorXd com_z = ref.com.col(2);
  std::printf("whole-body CoM (URDF chain) vs preview CoM: %.3e m (tol 1e-8), vs the reference's "
              "CoM column %.3e m (tol 1e-12); CoM height %.4f..%.4f m (cart-table z_c 0.814)\n",
              com_error, com_column_error, com_z.minCoeff(), com_z.maxCoeff());
  EXPECT_LT(com_error, 1e-8);
  EXPECT_LT(com_column_error, 1e-12);
}

// Multi-body ZMP of the joint reference (full rigid-body model, not the cart table):
//   p_x = c_x - (c_z c''_x + dL_y / M) / (c''_z + g),  p_y = c_y - (c_z c''_y - dL_x / M) / (c''_z
//   + g)
// with L the angular momentum about the CoM, L = sum m_i (c_i - c) x c'_i + R_i I_i R_i^T w_i,
// all rates by central differences of the link poses (URDF chain of the test helper).
TEST_F(WalkingPatternTest, MultibodyZmpInsideSupportPolygon) {
  const JointReference& ref = pattern_->reference;
  const FootstepPlan& plan = pattern_->plan;
  const int n = ref.n_samples();
  const double T = ref.period, g = 9.81;
  struct LinkState {
    double mass;
    Eigen::Vector3d com;
    Eigen::Matrix3d rotation, inertia;
  };
  std::vector<std::vector<LinkState>> links(n);
  Eigen::MatrixX3d com(n, 3);
  double total_mass = 0.0;
  for (int k = 0; k < n; ++k) {
    const Eigen::Isometry3d base = base_pose(ref, k);
    const auto named = named_angles(ref, k);
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    total_mass = 0.0;
    for (const auto& [name, link] : urdf_->links_) {
      if (!link->inertial)
        continue;
      const auto& in = *link->inertial;
      const Eigen::Isometry3d pose = base * link_pose(*urdf_, name, named);
      const Eigen::Isometry3d inertial_frame =
          pose * plantar::walking::testing::to_isometry(in.origin);
      Eigen::Matrix3d inertia;
      inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      links[k].push_back({in.mass, inertial_frame.translation(), inertial_frame.linear(), inertia});
      moment += in.mass * inertial_frame.translation();
      total_mass += in.mass;
    }
    com.row(k) = (moment / total_mass).transpose();
  }
  auto angular_momentum = [&](int k) {
    Eigen::Vector3d L = Eigen::Vector3d::Zero();
    const Eigen::Vector3d c = com.row(k).transpose();
    for (size_t i = 0; i < links[k].size(); ++i) {
      const LinkState& s = links[k][i];
      const Eigen::Vector3d velocity = (links[k + 1][i].com - links[k - 1][i].com) / (2 * T);
      const Eigen::AngleAxisd turn(links[k + 1][i].rotation * links[k - 1][i].rotation.transpose());
      const Eigen::Vector3d omega = turn.angle() * turn.axis() / (2 * T);
      L += s.mass * (s.com - c).cross(velocity) +
           s.rotation * s.inertia * s.rotation.transpose() * omega;
    }
    return L;
  };
  double min_margin = 1e9, min_margin_time = 0.0, max_difference = 0.0;
  for (int k = 2; k + 2 < n; ++k) {
    const Eigen::Vector3d acc =
        (com.row(k + 1) - 2 * com.row(k) + com.row(k - 1)).transpose() / (T * T);
    const Eigen::Vector3d dL = (angular_momentum(k + 1) - angular_momentum(k - 1)) / (2 * T);
    const double denominator = acc.z() + g;
    const Point zmp(com(k, 0) - (com(k, 2) * acc.x() + dL.y() / total_mass) / denominator,
                    com(k, 1) - (com(k, 2) * acc.y() - dL.x() / total_mass) / denominator);
    std::vector<Point> corners;
    if (plan.phase[k] != SupportPhase::left_support)
      add_sole_corners(corners, plan.right_sole.row(k).transpose(), plan.right_yaw(k));
    if (plan.phase[k] != SupportPhase::right_support)
      add_sole_corners(corners, plan.left_sole.row(k).transpose(), plan.left_yaw(k));
    const double margin = inside_margin(convex_hull(corners), zmp);
    if (margin < min_margin) {
      min_margin = margin;
      min_margin_time = plan.time(k);
    }
    max_difference =
        std::max(max_difference, (zmp - pattern_->cart_table_zmp.row(k).transpose()).norm());
  }
  std::printf("multi-body ZMP of q_ref: min margin %.4f m at t = %.3f s (tol > 0.005 m); max "
              "distance to the cart-table ZMP %.4f m\n",
              min_margin, min_margin_time, max_difference);
  EXPECT_GT(min_margin, 0.005);
}

TEST_F(WalkingPatternTest, SwingFeetLandAtRestOnFootsteps) {
  // Profiles: zero velocity and acceleration at both ends, checked by central differences.
  const double h = 1e-5;
  double max_derivative_mismatch = 0.0;
  for (double tau = 0.05; tau < 1.0; tau += 0.05)
    for (auto profile : {&quintic_transition, &swing_height_profile}) {
      const Eigen::Vector3d v = profile(tau), vp = profile(tau + h), vm = profile(tau - h);
      max_derivative_mismatch =
          std::max({max_derivative_mismatch, std::abs((vp(0) - vm(0)) / (2 * h) - v(1)),
                    std::abs((vp(1) - vm(1)) / (2 * h) - v(2))});
    }
  const Eigen::Vector3d s0 = quintic_transition(0.0), s1 = quintic_transition(1.0);
  const Eigen::Vector3d h0 = swing_height_profile(0.0), h1 = swing_height_profile(1.0);
  std::printf("profiles: s(0..1) = %.1f..%.1f, h(1/2) = %.3f, end derivatives max %.1e, "
              "finite-difference mismatch %.2e (tol 1e-6)\n",
              s0(0), s1(0), swing_height_profile(0.5)(0),
              std::max({s0.tail<2>().cwiseAbs().maxCoeff(), s1.tail<2>().cwiseAbs().maxCoeff(),
                        h0.cwiseAbs().maxCoeff(), h1.cwiseAbs().maxCoeff()}),
              max_derivative_mismatch);
  EXPECT_EQ(s0.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(h0.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(h1.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((s1 - Eigen::Vector3d(1, 0, 0)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(swing_height_profile(0.5)(0), 1.0, 1e-15);
  EXPECT_LT(max_derivative_mismatch, 1e-6);

  // In the sampled plan: each swing sole ends on its footstep; its speed over the last and
  // first samples of the swing is ~0 (a quintic: |v| <= 30 (T/T_ss)^2 travel / T_ss).
  const WalkingParameters walk;
  const FootstepPlan& plan = pattern_->plan;
  const double T = plan.time(1) - plan.time(0);
  double max_landing_error = 0.0, max_touchdown_speed = 0.0, max_apex = 0.0;
  size_t step = 0;
  for (int k = 1; k < plan.n_samples; ++k) {
    const bool was_swing = plan.phase[k - 1] != SupportPhase::double_support;
    const bool lifted = plan.phase[k - 1] == SupportPhase::double_support &&
                        plan.phase[k] != SupportPhase::double_support;
    const bool right_swing_prev = plan.phase[k - 1] == SupportPhase::left_support;
    const bool right_swing_now = plan.phase[k] == SupportPhase::left_support;
    max_apex = std::max({max_apex, plan.right_sole(k, 2), plan.left_sole(k, 2)});
    if (lifted) {
      const auto& sole = right_swing_now ? plan.right_sole : plan.left_sole;
      max_touchdown_speed =
          std::max(max_touchdown_speed, (sole.row(k + 1) - sole.row(k)).norm() / T);
    }
    if (was_swing && plan.phase[k] != plan.phase[k - 1]) { // touchdown at sample k
      const auto& sole = right_swing_prev ? plan.right_sole : plan.left_sole;
      const Eigen::Vector3d target(walk.footsteps[step].x, walk.footsteps[step].y, 0.0);
      max_landing_error = std::max(max_landing_error, (sole.row(k).transpose() - target).norm());
      max_touchdown_speed =
          std::max(max_touchdown_speed, (sole.row(k) - sole.row(k - 1)).norm() / T);
      ++step;
    }
  }
  // A sample may fall just before the phase switch, so bound by two samples of the quintic:
  // (travel * 10 + height * 64) (2 T / T_ss)^3 / T (s ~ 10 tau^3, h ~ 64 tau^3 near the ends;
  // the analytic swing velocity and acceleration are exactly 0 there).
  const double speed_bound = (walk.max_step_length * 10.0 + walk.step_height * 64.0) *
                             std::pow(2.0 * T / walk.single_support_time, 3) / T;
  std::printf("%zu landings: position error %.2e m (tol 1e-12), lift-off/touchdown speed over "
              "one sample %.2e m/s (tol %.2e), apex %.4f m (step height 0.07)\n",
              step, max_landing_error, max_touchdown_speed, speed_bound, max_apex);
  EXPECT_EQ(step, walk.footsteps.size());
  EXPECT_LT(max_landing_error, 1e-12);
  EXPECT_LT(max_touchdown_speed, speed_bound);
  EXPECT_NEAR(max_apex, walk.step_height, 1e-4);
}

TEST_F(WalkingPatternTest, JointReferenceRealisesPlanWithinLimits) {
  const JointReference& ref = pattern_->reference;
  const FootstepPlan& plan = pattern_->plan;
  // Sole poses from q_ref by the URDF chain (urdfdom transforms), against the plan.
  const auto sole_links = hrp2_description().sole_frames;
  EXPECT_EQ(ref.joint_names, humanoid_->joint_names);
  double max_sole_error = 0.0, max_sole_tilt = 0.0;
  double max_waist_speed = 0.0;
  for (int k = 0; k < ref.n_samples(); ++k) {
    const Eigen::Isometry3d base = base_pose(ref, k);
    const auto named = named_angles(ref, k);
    for (int side = 0; side < 2; ++side) {
      const Eigen::Isometry3d sole = base * link_pose(*urdf_, sole_links[side], named);
      const auto& planned = side == 0 ? plan.right_sole : plan.left_sole;
      const double yaw = side == 0 ? plan.right_yaw(k) : plan.left_yaw(k);
      max_sole_error =
          std::max(max_sole_error, (sole.translation() - planned.row(k).transpose()).norm());
      const Eigen::Matrix3d expected =
          Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      max_sole_tilt =
          std::max(max_sole_tilt, Eigen::AngleAxisd(expected.transpose() * sole.linear()).angle());
    }
    if (k > 0) // forward speed of the reference point (the waist)
      max_waist_speed = std::max(
          max_waist_speed, (ref.base_position(k, 0) - ref.base_position(k - 1, 0)) / ref.period);
  }
  double violation, speed_ratio;
  std::string joint;
  check_limits(*urdf_, ref, violation, speed_ratio, joint);
  // Leg joints only (the upper body is constant: the posture).
  double leg_margin = 1e9;
  std::string leg_joint;
  std::vector<bool> is_leg(ref.q.cols(), false);
  for (const auto& columns : humanoid_->leg_columns)
    for (int j : columns) {
      is_leg[j] = true;
      const auto limits = urdf_->getJoint(ref.joint_names[j])->limits;
      const double margin = std::min(limits->upper - ref.q.col(j).maxCoeff(),
                                     ref.q.col(j).minCoeff() - limits->lower);
      if (margin < leg_margin) {
        leg_margin = margin;
        leg_joint = ref.joint_names[j];
      }
    }
  double max_posture_error = 0.0;
  for (int j = 0; j < ref.q.cols(); ++j)
    if (!is_leg[j])
      max_posture_error = std::max(max_posture_error,
                                   (ref.q.col(j).array() - humanoid_->posture[j]).abs().maxCoeff());
  std::printf("worst leg joint-limit margin %.4f rad (%s); other joints vs posture %.1e rad\n",
              leg_margin, leg_joint.c_str(), max_posture_error);
  EXPECT_EQ(std::count(is_leg.begin(), is_leg.end(), true), 12);
  EXPECT_EQ(max_posture_error, 0.0);
  // Continuity: second differences of q bounded (no jumps, e.g. branch switches of the IK).
  double max_jump = 0.0;
  for (int k = 1; k + 1 < ref.n_samples(); ++k)
    max_jump = std::max(
        max_jump, (ref.q.row(k + 1) - 2 * ref.q.row(k) + ref.q.row(k - 1)).cwiseAbs().maxCoeff());
  std::printf(
      "q_ref realises the plan: sole position error %.2e m, orientation %.2e rad (tol "
      "1e-9); worst joint-limit margin %.4f rad (%s), max |dq/dt| = %.3f x velocity "
      "limit; max |second difference| %.2e rad (%.2f rad/s^2); peak forward waist speed %.3f "
      "m/s (paper: about 0.3, tol [0.25, 0.35])\n",
      max_sole_error, max_sole_tilt, -violation, joint.c_str(), speed_ratio, max_jump,
      max_jump / (ref.period * ref.period), max_waist_speed);
  EXPECT_LT(max_sole_error, 1e-9);
  EXPECT_LT(max_sole_tilt, 1e-9);
  EXPECT_LE(violation, 0.0);
  EXPECT_LT(speed_ratio, 1.0);
  EXPECT_LT(max_jump / (ref.period * ref.period), 200.0); // rad/s^2
  EXPECT_LT(max_waist_speed, 0.35);
  EXPECT_GT(max_waist_speed, 0.25);
}

TEST_F(WalkingPatternTest, SampleInterpolates) {
  const JointReference& ref = pattern_->reference;
  Eigen::VectorXd q(ref.q.cols());
  Eigen::Isometry3d base;
  double max_error = 0.0;
  for (int k = 100; k + 2 < ref.n_samples(); k += 97) {
    ref.sample(ref.time(k), q, base);
    max_error = std::max(max_error, (q - ref.q.row(k).transpose()).cwiseAbs().maxCoeff());
    // Catmull-Rom at a quarter period, from its matrix form 0.5 [-t^3 + 2t^2 - t,
    // 3t^3 - 5t^2 + 2, -3t^3 + 4t^2 + t, t^3 - t^2] at t = 1/4.
    const double w[4] = {-0.0703125, 0.8671875, 0.2265625, -0.0234375};
    ref.sample(ref.time(k) + 0.25 * ref.period, q, base);
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(ref.q.cols());
    Eigen::Vector3d expected_base = Eigen::Vector3d::Zero();
    for (int i = 0; i < 4; ++i) {
      expected += w[i] * ref.q.row(k - 1 + i).transpose();
      expected_base += w[i] * ref.base_position.row(k - 1 + i).transpose();
    }
    max_error = std::max(max_error, (q - expected).cwiseAbs().maxCoeff());
    max_error = std::max(max_error, (base.translation() - expected_base).norm());
  }
  std::printf("sample(): interpolation error %.2e (tol 1e-12)\n", max_error);
  EXPECT_LT(max_error, 1e-12);
}

TEST(WalkingPattern, BadInputIsReported) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  WalkingParameters walk;
  walk.single_support_time = -0.78;
  try {
    make_footstep_plan(walk);
    ADD_FAILURE() << "negative single_support_time accepted";
  } catch (const std::invalid_argument& e) {
    std::printf("rejected: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("single_support_time"), std::string::npos);
  }
  // A lateral step of 0.4 m is short enough for max_step_length but beyond the hip-roll
  // reach of the right leg: the generator must say which leg, when, and by how much.
  walk = WalkingParameters();
  walk.footsteps = {{0.0, -0.505, 0.0}, {0.0, 0.105, 0.0}};
  try {
    make_walking_pattern(model, humanoid, walk);
    ADD_FAILURE() << "unreachable plan accepted";
  } catch (const std::runtime_error& e) {
    std::printf("rejected: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("right leg"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("t = "), std::string::npos);
  }
}

// A walk placed on a terrain has its soles' ZMP targets off their centres (inside the support
// each rests on), its ZMP reference starting at their mean. The standing posture puts the CoM
// there: the cart-table model is linear, so moving every ZMP target by the same d moves the
// whole CoM and ZMP trajectory by d (up to the preview horizon's truncation). With the CoM over
// the sole centres instead, the preview servo first lurched the CoM onto the reference (a 13 cm
// excursion of the reference ZMP at the start of the FEM sole's walk on rough ground).
TEST(WalkingPattern, MovingEveryZmpTargetMovesTheComByAsMuch) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  const auto urdf = parse_hrp2();
  const WalkingParameters level;
  WalkingParameters moved = level;
  const Eigen::Vector2d d(-0.02, 0.015); // level soles without yaw: the sole axes are the world's
  for (Footstep* f : {&moved.initial_right, &moved.initial_left})
    f->zmp_x = d.x(), f->zmp_y = d.y();
  for (Footstep& f : moved.footsteps)
    f.zmp_x = d.x(), f.zmp_y = d.y();
  const WalkingPattern a = make_walking_pattern(model, humanoid, level);
  const WalkingPattern b = make_walking_pattern(model, humanoid, moved);
  ASSERT_EQ(a.plan.n_samples, b.plan.n_samples);
  double com_error = 0, zmp_error = 0;
  for (int k = 0; k < a.plan.n_samples; ++k) {
    const Eigen::Vector2d com_shift(b.com_x(k, 0) - a.com_x(k, 0), b.com_y(k, 0) - a.com_y(k, 0));
    com_error = std::max(com_error, (com_shift - d).norm());
    zmp_error = std::max(
        zmp_error, ((b.cart_table_zmp.row(k) - a.cart_table_zmp.row(k)).transpose() - d).norm());
  }
  // The reference's CoM at t = 0, recomputed with the test's own URDF chain.
  const auto [mass, com] = mass_and_com(*urdf, named_angles(b.reference, 0));
  const Eigen::Vector3d com_world = base_pose(b.reference, 0) * com;
  const Eigen::Vector2d start = b.plan.zmp_reference.row(0).transpose();
  std::printf("moved by (%.3f, %.3f) m: CoM trajectory off the moved level one by %.1e m, "
              "cart-table ZMP by %.1e m; CoM at t = 0 (%.6f, %.6f), ZMP reference (%.6f, %.6f)\n",
              d.x(), d.y(), com_error, zmp_error, com_world.x(), com_world.y(), start.x(),
              start.y());
  EXPECT_LT((start - d).norm(), 1e-15); // the level walk's starts at (0, 0)
  EXPECT_LT((com_world.head<2>() - start).norm(), 1e-6);
  // Not exact: the preview gains' sum over the finite horizon (1.6 s) does not cancel the state
  // gain, so a constant shift drives a small transient (7e-5 m of CoM, 3 mm of ZMP at the
  // start, decaying). With the CoM over the sole centres the CoM started |d| = 2.5 cm off.
  EXPECT_LT(com_error, 2e-4);
  EXPECT_LT(zmp_error, 5e-3);
}

TEST(StandingReference, ComOverFeetWithBentKnees) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  const auto urdf = parse_hrp2();
  const auto sole_links = hrp2_description().sole_frames;
  const JointReference ref = make_standing_reference(model, humanoid, 1.0, kRightSole, kLeftSole);
  const auto named = named_angles(ref, 0);
  const Eigen::Isometry3d base = base_pose(ref, 0);
  // CoM recomputed with the test's own URDF chain.
  const auto [mass, com] = mass_and_com(*urdf, named);
  const Eigen::Vector3d com_world = base * com;
  const Eigen::Vector3d right = (base * link_pose(*urdf, sole_links[0], named)).translation();
  const Eigen::Vector3d left = (base * link_pose(*urdf, sole_links[1], named)).translation();
  const int right_knee = humanoid.leg_columns[0][3], left_knee = humanoid.leg_columns[1][3];
  std::printf("standing: CoM (%.2e, %.2e, %.6f) m (CoM column off by %.1e m), soles z %.2e / "
              "%.2e, waist height %.4f m, knees %.2f / %.2f deg\n",
              com_world.x(), com_world.y(), com_world.z(),
              (ref.com.row(0).transpose() - com_world).norm(), right.z(), left.z(),
              base.translation().z(), ref.q(0, right_knee) * 180 / M_PI,
              ref.q(0, left_knee) * 180 / M_PI);
  EXPECT_NEAR(com_world.x(), 0.0, 1e-9);
  EXPECT_NEAR(com_world.y(), 0.0, 1e-9);
  EXPECT_NEAR(com_world.z(), 0.814, 1e-9);
  EXPECT_LT((ref.com.row(0).transpose() - com_world).norm(), 1e-12);
  EXPECT_NEAR(right.z(), 0.0, 1e-9);
  EXPECT_NEAR(left.y(), 0.105, 1e-9);
  EXPECT_GT(ref.q(0, right_knee), 0.3); // knees bent
  EXPECT_GT(ref.q(0, left_knee), 0.3);
  EXPECT_EQ((ref.q.row(0) - ref.q.row(ref.n_samples() - 1)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(ref.n_samples(), 201);
}

TEST(LeanReference, WaistRollRampsTo14_3Degrees) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  const auto urdf = parse_hrp2();
  const auto sole_links = hrp2_description().sole_frames;
  const LeanParameters lean;
  const JointReference ref = make_lean_reference(model, humanoid, lean, kRightSole, kLeftSole);
  double max_sole_drift = 0.0, previous_roll = -1.0, max_com_error = 0.0;
  bool monotone = true;
  const Eigen::Isometry3d base0 = base_pose(ref, 0);
  Eigen::Vector3d sole0[2];
  for (int side = 0; side < 2; ++side)
    sole0[side] = (base0 * link_pose(*urdf, sole_links[side], named_angles(ref, 0))).translation();
  for (int k = 0; k < ref.n_samples(); ++k) {
    const Eigen::Isometry3d base = base_pose(ref, k);
    const auto named = named_angles(ref, k);
    for (int side = 0; side < 2; ++side) {
      const Eigen::Isometry3d sole = base * link_pose(*urdf, sole_links[side], named);
      max_sole_drift = std::max(max_sole_drift, (sole.translation() - sole0[side]).norm() +
                                                    Eigen::AngleAxisd(sole.linear()).angle());
    }
    max_com_error =
        std::max(max_com_error,
                 (base * mass_and_com(*urdf, named).second - ref.com.row(k).transpose()).norm());
    const double roll = std::atan2(base.linear()(2, 1), base.linear()(2, 2));
    monotone = monotone && roll >= previous_roll - 1e-15;
    previous_roll = roll;
  }
  double violation, speed_ratio;
  std::string joint;
  check_limits(*urdf, ref, violation, speed_ratio, joint);
  std::printf("lean: final waist roll %.6f deg (commanded 14.3), feet drift %.2e (tol 1e-9), "
              "worst joint-limit margin %.4f rad (%s), CoM y moved %.4f m, CoM column vs URDF "
              "chain %.1e m\n",
              previous_roll * 180 / M_PI, max_sole_drift, -violation, joint.c_str(),
              ref.com(ref.n_samples() - 1, 1) - ref.com(0, 1), max_com_error);
  EXPECT_NEAR(sole0[0].y(), kRightSole.y, 1e-9);
  EXPECT_NEAR(sole0[1].y(), kLeftSole.y, 1e-9);
  EXPECT_NEAR(previous_roll * 180 / M_PI, 14.3, 1e-9);
  EXPECT_TRUE(monotone);
  EXPECT_LT(max_sole_drift, 1e-9);
  EXPECT_LT(max_com_error, 1e-12);
  EXPECT_LE(violation, 0.0);
  LeanParameters bad;
  bad.ramp_time = 0.0;
  EXPECT_THROW(make_lean_reference(model, humanoid, bad, kRightSole, kLeftSole),
               std::invalid_argument);
}

} // namespace
