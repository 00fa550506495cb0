// Numerical leg IK (NumericalLegIk) against independent values: forward kinematics (the
// project's and the urdfdom chain of urdf_fk.h), the analytic solver solve_leg_ik, and finite
// differences of the error. Models: the HRP-2-like robot and models/test/offset_leg.urdf, whose
// legs the analytic IK rejects. Joint and frame names live here only.
#include "multibody/kinematics.h"
#include "multibody/urdf_loader.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/leg_geometry.h"
#include "multibody/walking/leg_ik.h"
#include "multibody/walking/numerical_leg_ik.h"
#include "tests/multibody/walking/hrp2_humanoid.h"
#include "tests/multibody/walking/urdf_fk.h"

#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

// Counts every heap allocation (Eigen's and operator new's go through malloc): by interposing
// glibc's malloc in this executable, or under AddressSanitizer (which owns malloc) by its
// allocation hook (tests/allocation_counter.h).
#if defined(__SANITIZE_ADDRESS__)
#include "tests/allocation_counter.h"
namespace {
[[maybe_unused]] const bool g_count_from_start = (plantar::testing::counting = true);
} // namespace
#define PLANTAR_COUNT_MALLOC 1
#elif defined(__GLIBC__)
namespace {
std::atomic<long> g_mallocs{0};
} // namespace
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* malloc(std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
#define PLANTAR_COUNT_MALLOC 1
#endif

namespace {

/// Heap allocations so far (0 where malloc is not counted).
long g_mallocs_value() {
#if defined(__SANITIZE_ADDRESS__)
  return plantar::testing::n_allocations.load();
#elif defined(PLANTAR_COUNT_MALLOC)
  return g_mallocs.load();
#else
  return 0;
#endif
}

using plantar::multibody::build_model_from_urdf;
using plantar::multibody::Data;
using plantar::multibody::Model;
using plantar::multibody::SE3;
using plantar::multibody::Vector6d;
using namespace plantar::walking;

const std::string kHrp2 = std::string(PLANTAR_SOURCE_DIR) + "/models/hrp2/hrp2.urdf";
const std::string kOffsetLeg = std::string(PLANTAR_SOURCE_DIR) + "/models/test/offset_leg.urdf";

/// A leg of a test robot: its joint names (root to tip) and sole frame.
struct LegNames {
  std::vector<std::string> joints;
  std::string sole;
};

LegNames hrp2_leg(LegSide side) {
  const std::string prefix = side == LegSide::right ? "RLEG_JOINT" : "LLEG_JOINT";
  LegNames names;
  for (int k = 0; k < 6; ++k)
    names.joints.push_back(prefix + std::to_string(k));
  names.sole = side == LegSide::right ? "r_sole" : "l_sole";
  return names;
}

LegNames offset_leg(LegSide side) {
  const std::string p = side == LegSide::right ? "r_" : "l_";
  return {{p + "hip_pitch", p + "hip_roll", p + "hip_yaw", p + "knee", p + "ankle_pitch",
           p + "ankle_roll"},
          p + "sole"};
}

std::vector<int> joint_ids(const Model& model, const LegNames& names) {
  std::vector<int> ids;
  for (const auto& name : names.joints)
    ids.push_back(model.joint_id(name));
  return ids;
}

/// Writes the six leg angles into q (order of `joints`).
void set_leg(const Model& model, const std::vector<int>& joints,
             const Eigen::Matrix<double, 6, 1>& a, Eigen::VectorXd& q) {
  for (int k = 0; k < 6; ++k)
    q[model.idx_q[joints[k]]] = a[k];
}

Eigen::Matrix<double, 6, 1> get_leg(const Model& model, const std::vector<int>& joints,
                                    const Eigen::VectorXd& q) {
  Eigen::Matrix<double, 6, 1> a;
  for (int k = 0; k < 6; ++k)
    a[k] = q[model.idx_q[joints[k]]];
  return a;
}

/// Random leg angles uniformly inside the limits, knee (index knee) >= 0.05 rad.
Eigen::Matrix<double, 6, 1> random_leg(const Model& model, const std::vector<int>& joints, int knee,
                                       std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix<double, 6, 1> a;
  for (int k = 0; k < 6; ++k) {
    const int iq = model.idx_q[joints[k]];
    a[k] = model.lower_position_limit[iq] +
           unit(rng) * (model.upper_position_limit[iq] - model.lower_position_limit[iq]);
  }
  a[knee] = std::max(a[knee], 0.05);
  return a;
}

/// Random floating-base pose written into q[0..6].
void random_base(std::mt19937& rng, Eigen::VectorXd& q) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  q.head<3>() = Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, 0.5 + unit(rng));
  Eigen::Vector4d quat(normal(rng), normal(rng), normal(rng), normal(rng));
  q.segment<4>(3) = quat.normalized(); // (x, y, z, w)
}

SE3 frame_pose(const Model& model, const Eigen::VectorXd& q, int frame) {
  Data data(model);
  plantar::multibody::forward_kinematics(model, data, q);
  return plantar::multibody::frame_placement(model, data, frame);
}

double position_error(const SE3& a, const SE3& b) {
  return (a.translation - b.translation).norm();
}
/// Angle of a.R b.R^T (Eigen's AngleAxis, independent of log3).
double rotation_error(const SE3& a, const SE3& b) {
  return Eigen::AngleAxisd(a.rotation * b.rotation.transpose()).angle();
}

bool within_limits(const Model& model, const std::vector<int>& joints, const Eigen::VectorXd& q) {
  for (int j : joints) {
    const int iq = model.idx_q[j];
    if (q[iq] < model.lower_position_limit[iq] || q[iq] > model.upper_position_limit[iq])
      return false;
  }
  return true;
}

Eigen::Isometry3d to_isometry(const SE3& x) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = x.rotation;
  out.translation() = x.translation;
  return out;
}

/// HRP-2 half-sitting legs (bent knees), the start of the round trips.
Eigen::Matrix<double, 6, 1> hrp2_half_sitting() {
  Eigen::Matrix<double, 6, 1> a;
  a << 0.0, 0.0, -0.453786, 0.872665, -0.418879, 0.0;
  return a;
}

Eigen::Matrix<double, 6, 1> offset_leg_bent() {
  Eigen::Matrix<double, 6, 1> a;
  a << -0.4, 0.0, 0.0, 0.8, -0.5, 0.0;
  return a;
}

#ifdef PLANTAR_COUNT_MALLOC
TEST(MallocCounter, CountsEigenAllocations) {
  // The counter must see Eigen's heap allocations, otherwise the walk test proves nothing.
  const long before = g_mallocs_value();
  volatile double sink = 0.0;
  {
    Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(100, 0.0, 1.0);
    sink = v.sum();
  }
  EXPECT_GT(g_mallocs_value() - before, 0) << sink;
}
#endif

TEST(Log3, InverseOfExp3) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  double max_error = 0.0;
  for (double angle :
       {0.0, 1e-12, 1e-7, 1e-4, 2e-4, 1e-2, 0.5, 2.0, 3.0, M_PI - 1e-6, M_PI - 1e-9}) {
    for (int sample = 0; sample < 20; ++sample) {
      const Eigen::Vector3d axis =
          Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
      const Eigen::Vector3d w = angle * axis;
      const Eigen::Matrix3d r = plantar::multibody::exp3_quaternion(w).toRotationMatrix();
      const Eigen::Vector3d back = plantar::multibody::log3(r);
      max_error = std::max(max_error, (back - w).norm());
    }
  }
  // At pi: either of the two opposite vectors.
  const Eigen::Vector3d half_turn = plantar::multibody::log3(
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d(0.6, 0.0, 0.8)).toRotationMatrix());
  std::printf("log3(exp3(w)) - w: max %.3e (tol 1e-12; 0 <= |w| < pi); at pi: |w| - pi = %.3e, "
              "|w x axis| = %.3e\n",
              max_error, half_turn.norm() - M_PI,
              half_turn.cross(Eigen::Vector3d(0.6, 0.0, 0.8)).norm());
  EXPECT_LT(max_error, 1e-12);
  EXPECT_NEAR(half_turn.norm(), M_PI, 1e-12);
  EXPECT_LT(half_turn.cross(Eigen::Vector3d(0.6, 0.0, 0.8)).norm(), 1e-12);
}

/// The analytic IK's branch test: hip (LINK1 origin) above the ankle along the ankle-pitch link
/// (LINK4) z axis by more than 1 mm (beta > 0, see leg_ik.h).
bool hrp2_beta_positive(const Model& model, LegSide side, const Eigen::VectorXd& q) {
  const std::string prefix = side == LegSide::right ? "RLEG" : "LLEG";
  const SE3 ankle_link = frame_pose(model, q, model.frame_id(prefix + "_LINK4"));
  const Eigen::Vector3d hip = frame_pose(model, q, model.frame_id(prefix + "_LINK1")).translation;
  return ankle_link.act_inv_point(hip).z() > 1e-3;
}

SE3 base_pose(const Eigen::VectorXd& q) {
  return SE3(Eigen::Quaterniond(q[6], q[3], q[4], q[5]).toRotationMatrix(), q.head<3>());
}

/// Round trips on one leg of `model`: random angles within the limits (knee >= 0.05 rad), random
/// base pose, target = FK; solved from `start` (legs) with the same base.
struct RoundTrips {
  int samples = 0, failed = 0, restarted = 0, max_iterations = 0;
  long iterations = 0;
  double max_position = 0.0, max_rotation = 0.0;
  bool within_limits = true, rest_unchanged = true;
  std::vector<Eigen::VectorXd> q_true, q_solved; ///< per solved sample
  std::vector<SE3> targets;
};

RoundTrips round_trips(const Model& model, const LegNames& names,
                       const Eigen::Matrix<double, 6, 1>& start, int n_samples, unsigned seed) {
  const std::vector<int> joints = joint_ids(model, names);
  const int sole = model.frame_id(names.sole);
  NumericalLegIk ik(model, joints, sole);
  std::mt19937 rng(seed);
  RoundTrips out;
  for (int sample = 0; sample < n_samples; ++sample) {
    Eigen::VectorXd q_true = model.neutral_configuration();
    random_base(rng, q_true);
    set_leg(model, joints, random_leg(model, joints, 3, rng), q_true);
    const SE3 target = frame_pose(model, q_true, sole);
    Eigen::VectorXd q = q_true;
    set_leg(model, joints, start, q);
    ++out.samples;
    NumericalIkReport report;
    try {
      report = ik.solve(q, target);
    } catch (const std::runtime_error& e) {
      ++out.failed;
      std::printf("  failed: %s\n", e.what());
      continue;
    }
    out.restarted += report.restarts > 0;
    out.iterations += report.iterations;
    out.max_iterations = std::max(out.max_iterations, report.iterations);
    // Only the chain's coordinates changed.
    Eigen::VectorXd rest = q, rest_true = q_true;
    set_leg(model, joints, Eigen::Matrix<double, 6, 1>::Zero(), rest);
    set_leg(model, joints, Eigen::Matrix<double, 6, 1>::Zero(), rest_true);
    out.rest_unchanged = out.rest_unchanged && rest == rest_true;
    // The pose reached, by a fresh Data (independent of the solver's workspace).
    const SE3 reached = frame_pose(model, q, sole);
    out.max_position = std::max(out.max_position, position_error(reached, target));
    out.max_rotation = std::max(out.max_rotation, rotation_error(reached, target));
    out.within_limits = out.within_limits && within_limits(model, joints, q);
    out.q_true.push_back(q_true);
    out.q_solved.push_back(q);
    out.targets.push_back(target);
  }
  return out;
}

void print_round_trips(const char* what, const RoundTrips& r) {
  std::printf("%s: %d/%d solved (%d failed, %d needed restarts), iterations mean %.2f max %d; "
              "sole error %.3e m, %.3e rad (tol 1e-9 each); within limits: %s\n",
              what, r.samples - r.failed, r.samples, r.failed, r.restarted,
              double(r.iterations) / std::max(r.samples - r.failed, 1), r.max_iterations,
              r.max_position, r.max_rotation, r.within_limits ? "yes" : "NO");
}

void expect_round_trips(const RoundTrips& r) {
  EXPECT_EQ(r.failed, 0);
  EXPECT_LT(r.max_position, 1e-9);
  EXPECT_LT(r.max_rotation, 1e-9);
  EXPECT_TRUE(r.within_limits);
  EXPECT_TRUE(r.rest_unchanged);
}

TEST(NumericalLegIk, Hrp2RoundTripsAgreeWithAnalyticIk) {
  const Model model = build_model_from_urdf(kHrp2);
  const auto urdf = urdf::parseURDFFile(kHrp2);
  ASSERT_TRUE(urdf);
  const plantar::walking::Humanoid humanoid(model, plantar::walking::testing::hrp2_description());
  for (LegSide side : {LegSide::right, LegSide::left}) {
    const LegNames names = hrp2_leg(side);
    const std::vector<int> joints = joint_ids(model, names);
    const RoundTrips r = round_trips(model, names, hrp2_half_sitting(), 1000,
                                     side == LegSide::right ? 20240529u : 20240530u);
    print_round_trips(side == LegSide::right ? "HRP-2 right leg from half-sitting"
                                             : "HRP-2 left leg from half-sitting",
                      r);
    expect_round_trips(r);
    const LegGeometry leg = read_leg_geometry(model, humanoid, side);
    // The angles of a solution within the pose tolerance 1e-10 are only as accurate as
    // 1e-10 / sigma_min(E) (sigma_min ~ 1e-2 with a knee bent 0.05 rad): each solution is also
    // refined to 1e-13 (from itself, 0-1 iterations) for the comparison with the closed form.
    NumericalIkSettings tight;
    tight.position_tolerance = tight.rotation_tolerance = 1e-13;
    NumericalLegIk refine(model, joints, model.frame_id(names.sole), tight);
    int compared = 0, target_other_branch = 0, solution_other_branch = 0;
    double max_difference = 0.0, max_refined_difference = 0.0, max_urdf_position = 0.0,
           max_urdf_rotation = 0.0;
    for (std::size_t i = 0; i < r.q_solved.size(); ++i) {
      const Eigen::VectorXd& q = r.q_solved[i];
      const Eigen::Matrix<double, 6, 1> solved = get_leg(model, joints, q);
      // The sole reached through the urdfdom chain (independent of plantar_multibody).
      std::map<std::string, double> named;
      for (int k = 0; k < 6; ++k)
        named[names.joints[k]] = solved[k];
      const Eigen::Isometry3d urdf_sole =
          to_isometry(base_pose(q)) *
          plantar::walking::testing::link_pose(*urdf, names.sole, named);
      max_urdf_position =
          std::max(max_urdf_position, (urdf_sole.translation() - r.targets[i].translation).norm());
      max_urdf_rotation = std::max(
          max_urdf_rotation,
          Eigen::AngleAxisd(urdf_sole.linear() * r.targets[i].rotation.transpose()).angle());
      // The analytic solver's branch: knee >= 0 and beta >= 0.
      if (!hrp2_beta_positive(model, side, r.q_true[i])) {
        ++target_other_branch;
        continue;
      }
      if (solved[3] < 0.0 || !hrp2_beta_positive(model, side, q)) {
        ++solution_other_branch; // a valid solution, the one the closed form does not return
        continue;
      }
      LegAngles analytic;
      solve_leg_ik(leg, to_isometry(base_pose(q)), to_isometry(r.targets[i]), analytic);
      max_difference = std::max(max_difference, (solved - analytic).cwiseAbs().maxCoeff());
      Eigen::VectorXd q_refined = q;
      refine.solve(q_refined, r.targets[i]);
      max_refined_difference =
          std::max(max_refined_difference,
                   (get_leg(model, joints, q_refined) - analytic).cwiseAbs().maxCoeff());
      ++compared;
    }
    std::printf("  urdfdom chain: sole error %.3e m, %.3e rad; vs solve_leg_ik: %d compared (%d "
                "targets and %d solutions on the beta < 0 branch skipped), max angle difference "
                "%.3e rad (tolerance 1e-10: for information), %.3e rad refined to 1e-13 (tol "
                "1e-8)\n",
                max_urdf_position, max_urdf_rotation, compared, target_other_branch,
                solution_other_branch, max_difference, max_refined_difference);
    EXPECT_LT(max_urdf_position, 1e-9);
    EXPECT_LT(max_urdf_rotation, 1e-9);
    EXPECT_LT(max_refined_difference, 1e-8);
    EXPECT_GT(compared, 900);
  }
}

TEST(NumericalLegIk, OffsetLegRoundTrips) {
  const Model model = build_model_from_urdf(kOffsetLeg);
  for (LegSide side : {LegSide::right, LegSide::left}) {
    const RoundTrips r = round_trips(model, offset_leg(side), offset_leg_bent(), 1000,
                                     side == LegSide::right ? 31u : 32u);
    print_round_trips(side == LegSide::right ? "offset leg, right, from a bent pose"
                                             : "offset leg, left, from a bent pose",
                      r);
    expect_round_trips(r);
  }
}

// kestrel (models/kestrel, the project's second humanoid): hip pitch-roll-yaw with offsets, knee
// and ankle offsets along x, its sole frames placed on the foot links as its scenes place them.
TEST(NumericalLegIk, KestrelRoundTrips) {
  Model model =
      build_model_from_urdf(std::string(PLANTAR_SOURCE_DIR) + "/models/kestrel/kestrel.urdf");
  plantar::walking::HumanoidDescription description;
  description.base_link = "pelvis";
  description.foot_links = {"r_foot", "l_foot"};
  const SE3 sole(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.02, 0.0, -0.055));
  description.sole_placements = {sole, sole};
  plantar::walking::add_sole_frames(model, description);
  const plantar::walking::Humanoid humanoid(model, description);
  for (LegSide side : {LegSide::right, LegSide::left}) {
    LegNames names = offset_leg(side);
    names.sole = plantar::walking::placed_sole_frame_name(description, side);
    // The Humanoid finds the same chain from the foot link up to the pelvis.
    const std::vector<int> joints = joint_ids(model, names);
    for (int k = 0; k < 6; ++k)
      EXPECT_EQ(humanoid.leg_joints[static_cast<int>(side)][k], joints[k]);
    std::string reason;
    EXPECT_FALSE(plantar::walking::analytic_leg_geometry(model, humanoid, side, reason));
    std::printf("kestrel %s leg: no closed form (%s)\n", to_string(side), reason.c_str());
    const RoundTrips r =
        round_trips(model, names, offset_leg_bent(), 1000, side == LegSide::right ? 41u : 42u);
    print_round_trips(side == LegSide::right ? "kestrel, right, from a bent pose"
                                             : "kestrel, left, from a bent pose",
                      r);
    expect_round_trips(r);
  }
}

TEST(NumericalLegIk, ErrorJacobianMatchesFiniteDifferences) {
  struct Robot {
    std::string urdf;
    LegNames leg;
  };
  const std::vector<Robot> robots = {{kHrp2, hrp2_leg(LegSide::right)},
                                     {kHrp2, hrp2_leg(LegSide::left)},
                                     {kOffsetLeg, offset_leg(LegSide::right)},
                                     {kOffsetLeg, offset_leg(LegSide::left)}};
  std::mt19937 rng(99);
  double max_relative = 0.0, max_rotation_error = 0.0;
  int n_checked = 0;
  for (const Robot& robot : robots) {
    const Model model = build_model_from_urdf(robot.urdf);
    const std::vector<int> joints = joint_ids(model, robot.leg);
    const int sole = model.frame_id(robot.leg.sole);
    NumericalLegIk ik(model, joints, sole);
    for (int sample = 0; sample < 50; ++sample) {
      // A random configuration and a random reachable target: the rotation error is up to a
      // few rad, where J_l^-1 is far from the identity.
      Eigen::VectorXd q = model.neutral_configuration();
      random_base(rng, q);
      Eigen::VectorXd q_target = q;
      set_leg(model, joints, random_leg(model, joints, 3, rng), q);
      set_leg(model, joints, random_leg(model, joints, 3, rng), q_target);
      const SE3 target = frame_pose(model, q_target, sole);
      Vector6d error;
      Eigen::MatrixXd jacobian(6, 6);
      ik.error_and_jacobian(q, target, error, jacobian);
      if (error.tail<3>().norm() > 3.0)
        continue; // log3 jumps at pi: no derivative there
      max_rotation_error = std::max(max_rotation_error, error.tail<3>().norm());
      // e against an independent evaluation (fresh Data, Eigen's AngleAxis for the log).
      const SE3 pose = frame_pose(model, q, sole);
      const Eigen::AngleAxisd angle_axis(pose.rotation * target.rotation.transpose());
      EXPECT_LT((error.head<3>() - (pose.translation - target.translation)).norm(), 1e-15);
      EXPECT_LT((error.tail<3>() - angle_axis.angle() * angle_axis.axis()).norm(), 1e-12);
      Eigen::MatrixXd numerical(6, 6);
      const double h = 1e-6;
      for (int k = 0; k < 6; ++k) {
        Eigen::VectorXd qp = q, qm = q;
        qp[model.idx_q[joints[k]]] += h;
        qm[model.idx_q[joints[k]]] -= h;
        Vector6d ep, em;
        Eigen::MatrixXd unused(6, 6);
        ik.error_and_jacobian(qp, target, ep, unused);
        ik.error_and_jacobian(qm, target, em, unused);
        numerical.col(k) = (ep - em) / (2.0 * h);
      }
      max_relative = std::max(max_relative, (numerical - jacobian).cwiseAbs().maxCoeff() /
                                                jacobian.cwiseAbs().maxCoeff());
      ++n_checked;
    }
  }
  std::printf("error Jacobian vs central differences (h = 1e-6): %d configurations (rotation "
              "errors up to %.2f rad), max |E_fd - E| / max |E| = %.3e (tol 1e-6)\n",
              n_checked, max_rotation_error, max_relative);
  EXPECT_GT(n_checked, 150);
  EXPECT_LT(max_relative, 1e-6);
}

TEST(NumericalLegIk, JointLimits) {
  const Model model = build_model_from_urdf(kHrp2);
  const LegNames names = hrp2_leg(LegSide::right);
  const std::vector<int> joints = joint_ids(model, names);
  const int sole = model.frame_id(names.sole);
  NumericalLegIk ik(model, joints, sole);
  const int yaw_q = model.idx_q[joints[0]];
  const double yaw_upper = model.upper_position_limit[yaw_q];
  Eigen::Matrix<double, 6, 1> pose;
  pose << 0.0, -0.1, -0.6, 1.0, -0.4, 0.1;

  // Hip yaw 0.15 rad past its upper limit: no solution inside the limits (the other IK branches
  // need a backward knee or a yaw turned by pi).
  Eigen::VectorXd q_true = model.neutral_configuration();
  pose[0] = yaw_upper + 0.15;
  set_leg(model, joints, pose, q_true);
  const SE3 past = frame_pose(model, q_true, sole);
  Eigen::VectorXd q = model.neutral_configuration();
  set_leg(model, joints, hrp2_half_sitting(), q);
  const Eigen::VectorXd q_start = q;
  std::string message;
  try {
    ik.solve(q, past);
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  std::printf("target past the hip yaw limit: %s\n", message.c_str());
  EXPECT_NE(message.find("RLEG_JOINT0 (upper limit 0.523599"), std::string::npos);
  EXPECT_NE(message.find("'r_sole'"), std::string::npos);
  EXPECT_EQ(q, q_start); // unchanged on failure

  // Hip yaw exactly at its upper limit: solved, with the yaw at the limit.
  pose[0] = yaw_upper;
  set_leg(model, joints, pose, q_true);
  const SE3 boundary = frame_pose(model, q_true, sole);
  const NumericalIkReport report = ik.solve(q, boundary);
  const SE3 reached = frame_pose(model, q, sole);
  std::printf("target with the hip yaw at its limit %.6f: yaw %.12f (limit - yaw = %.3e), %d "
              "iterations, sole error %.3e m, %.3e rad\n",
              yaw_upper, q[yaw_q], yaw_upper - q[yaw_q], report.iterations,
              position_error(reached, boundary), rotation_error(reached, boundary));
  EXPECT_LE(q[yaw_q], yaw_upper);
  EXPECT_LT(yaw_upper - q[yaw_q], 1e-9);
  EXPECT_LT(position_error(reached, boundary), 1e-9);
  EXPECT_LT(rotation_error(reached, boundary), 1e-9);
  EXPECT_TRUE(within_limits(model, joints, q));

  // A warm start outside the limits is clamped into them first.
  q = model.neutral_configuration();
  set_leg(model, joints, hrp2_half_sitting(), q);
  q[yaw_q] = yaw_upper + 1.0;
  ik.solve(q, boundary);
  EXPECT_LE(q[yaw_q], yaw_upper);
  EXPECT_LT(position_error(frame_pose(model, q, sole), boundary), 1e-9);
}

TEST(NumericalLegIk, UnreachableTargetThrows) {
  const Model model = build_model_from_urdf(kHrp2);
  const LegNames names = hrp2_leg(LegSide::right);
  const std::vector<int> joints = joint_ids(model, names);
  NumericalLegIk ik(model, joints, model.frame_id(names.sole));
  Eigen::VectorXd q = model.neutral_configuration();
  set_leg(model, joints, hrp2_half_sitting(), q);
  // Base at the origin: the hip is at (0, -0.06, 0), the straight leg reaches 0.705 m below it
  // (0.6 m hip to ankle, 0.105 m ankle to sole); the target is 1.2 m below.
  const SE3 straight = frame_pose(model, model.neutral_configuration(), model.frame_id("r_sole"));
  SE3 target = straight;
  target.translation.z() = -1.2;
  const double expected_residual = straight.translation.z() - target.translation.z();
  std::string message;
  try {
    ik.solve(q, target);
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  std::printf("unreachable target: %s\n", message.c_str());
  EXPECT_NE(message.find("'r_sole'"), std::string::npos);
  const auto at = message.find("residual position error ");
  ASSERT_NE(at, std::string::npos);
  const double residual =
      std::stod(message.substr(at + std::string("residual position error ").size()));
  std::printf("residual %.6f m, straight-leg distance to the target %.6f m\n", residual,
              expected_residual);
  EXPECT_NEAR(residual, expected_residual, 1e-3);
}

TEST(NumericalLegIk, RejectsBadChains) {
  const Model model = build_model_from_urdf(kHrp2);
  const int r_sole = model.frame_id("r_sole");
  std::vector<int> joints = joint_ids(model, hrp2_leg(LegSide::right));
  auto message_of = [&](std::vector<int> chain, int frame) {
    try {
      NumericalLegIk ik(model, std::move(chain), frame);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::vector<int> other_leg = joints;
  other_leg[2] = model.joint_id("LLEG_JOINT2");
  EXPECT_NE(message_of(other_leg, r_sole).find("'LLEG_JOINT2' does not move frame 'r_sole'"),
            std::string::npos);
  std::vector<int> with_base = joints;
  with_base[0] = 1; // the free flyer
  EXPECT_NE(message_of(with_base, r_sole).find("not a 1-DoF"), std::string::npos);
  std::vector<int> twice = joints;
  twice[1] = twice[0];
  EXPECT_NE(message_of(twice, r_sole).find("appears twice"), std::string::npos);
  EXPECT_NE(message_of(joints, 100000).find("frame index"), std::string::npos);
  EXPECT_NO_THROW(NumericalLegIk(
      model, {joints[5], joints[0], joints[3], joints[1], joints[4], joints[2]}, r_sole));
}

TEST(NumericalLegIk, StraightLegSingularTarget) {
  // Target = the sole with straight legs (knee 0, the singular pose of the leg: the Jacobian
  // loses the leg-length direction): reached from half-sitting thanks to the damping; the error
  // along the leg is quadratic in the knee angle, so the knee ends near sqrt(tolerance).
  const Model model = build_model_from_urdf(kHrp2);
  const LegNames names = hrp2_leg(LegSide::right);
  const std::vector<int> joints = joint_ids(model, names);
  const int sole = model.frame_id(names.sole);
  NumericalLegIk ik(model, joints, sole);
  const SE3 target = frame_pose(model, model.neutral_configuration(), sole);
  Eigen::VectorXd q = model.neutral_configuration();
  set_leg(model, joints, hrp2_half_sitting(), q);
  const NumericalIkReport report = ik.solve(q, target);
  const SE3 reached = frame_pose(model, q, sole);
  std::printf("straight-leg target: %d iterations, sole error %.3e m, %.3e rad, max |q| %.3e rad "
              "(knee %.3e)\n",
              report.iterations, position_error(reached, target), rotation_error(reached, target),
              get_leg(model, joints, q).cwiseAbs().maxCoeff(), q[model.idx_q[joints[3]]]);
  EXPECT_LT(position_error(reached, target), 1e-9);
  EXPECT_LT(rotation_error(reached, target), 1e-9);
  EXPECT_LT(get_leg(model, joints, q).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LE(report.iterations, 40);
}

/// Smooth 0 -> 1 over tau in [0, 1] with zero velocity and acceleration at both ends.
double quintic(double tau) {
  return tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
}

TEST(NumericalLegIk, WalkSequenceWarmStarted) {
  // One step: the base moves 0.1 m forward, sways 0.03 m towards the stance (left) foot and yaws
  // 0.05 rad; the right sole swings 0.2 m forward (quintic in x and yaw, 0.1 rad), lifted by
  // 0.05 sin(pi tau) m; the left sole stays. 5 ms samples, each solve warm started from the last.
  struct Robot {
    const char* name;
    std::string urdf;
    LegNames right, left;
    Eigen::Matrix<double, 6, 1> start;
  };
  const std::vector<Robot> robots = {
      {"HRP-2", kHrp2, hrp2_leg(LegSide::right), hrp2_leg(LegSide::left), hrp2_half_sitting()},
      {"offset leg", kOffsetLeg, offset_leg(LegSide::right), offset_leg(LegSide::left),
       offset_leg_bent()}};
  for (const Robot& robot : robots) {
    const Model model = build_model_from_urdf(robot.urdf);
    const std::vector<int> right = joint_ids(model, robot.right);
    const std::vector<int> left = joint_ids(model, robot.left);
    const int r_sole = model.frame_id(robot.right.sole), l_sole = model.frame_id(robot.left.sole);
    NumericalLegIk ik_right(model, right, r_sole), ik_left(model, left, l_sole);
    Eigen::VectorXd q = model.neutral_configuration();
    set_leg(model, right, robot.start, q);
    set_leg(model, left, robot.start, q);
    const SE3 right0 = frame_pose(model, q, r_sole), left0 = frame_pose(model, q, l_sole);
    const double duration = 0.8, dt = 0.005;
    const int n_steps = static_cast<int>(std::lround(duration / dt));
    std::vector<Eigen::Matrix<double, 7, 1>> bases;
    std::vector<SE3> swing;
    for (int i = 0; i <= n_steps; ++i) {
      const double tau = i * dt / duration, s = quintic(tau);
      Eigen::Matrix<double, 7, 1> base;
      base.head<3>() = Eigen::Vector3d(0.1 * s, 0.03 * std::sin(M_PI * tau), 0.0);
      base.tail<4>() = Eigen::Quaterniond(Eigen::AngleAxisd(0.05 * s, Eigen::Vector3d::UnitZ()))
                           .coeffs(); // (x, y, z, w)
      bases.push_back(base);
      swing.emplace_back(
          Eigen::AngleAxisd(0.1 * s, Eigen::Vector3d::UnitZ()).toRotationMatrix() * right0.rotation,
          right0.translation + Eigen::Vector3d(0.2 * s, 0.0, 0.05 * std::sin(M_PI * tau)));
    }
    long total_iterations = 0, restarts = 0;
    int max_iterations = 0;
    double max_position = 0.0, max_rotation = 0.0, seconds = 1e30;
    const Eigen::VectorXd q_initial = q;
    const long mallocs_before = g_mallocs_value();
    // The sequence 10 times from the same initial q (identical results), for the best time.
    for (int repeat = 0; repeat < 10; ++repeat) {
      q = q_initial;
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i <= n_steps; ++i) {
        q.head<7>() = bases[i];
        const NumericalIkReport a = ik_right.solve(q, swing[i]);
        const NumericalIkReport b = ik_left.solve(q, left0);
        if (repeat > 0)
          continue;
        for (const NumericalIkReport& r : {a, b}) {
          total_iterations += r.iterations;
          max_iterations = std::max(max_iterations, r.iterations);
          restarts += r.restarts;
          max_position = std::max(max_position, r.position_error);
          max_rotation = std::max(max_rotation, r.rotation_error);
        }
      }
      seconds = std::min(
          seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    const long mallocs = g_mallocs_value() - mallocs_before;
    const int n_solves = 2 * (n_steps + 1);
    // Independent check of the last sample's poses.
    const SE3 r_end = frame_pose(model, q, r_sole), l_end = frame_pose(model, q, l_sole);
    std::printf("%s walk: %d warm-started solves, iterations mean %.2f max %d, %ld restarts, "
                "reported error max %.3e m %.3e rad, final sample %.3e m %.3e rad; "
                "heap allocations in solve(): %ld; %.2f us per solve (best of 10 runs)\n",
                robot.name, n_solves, double(total_iterations) / n_solves, max_iterations, restarts,
                max_position, max_rotation,
                std::max(position_error(r_end, swing.back()), position_error(l_end, left0)),
                std::max(rotation_error(r_end, swing.back()), rotation_error(l_end, left0)),
                mallocs, 1e6 * seconds / n_solves);
    EXPECT_LE(max_iterations, 4);
    EXPECT_EQ(restarts, 0);
    EXPECT_LT(position_error(r_end, swing.back()), 1e-9);
    EXPECT_LT(rotation_error(l_end, left0), 1e-9);
    EXPECT_TRUE(within_limits(model, right, q) && within_limits(model, left, q));
#ifdef PLANTAR_COUNT_MALLOC
    EXPECT_EQ(mallocs, 0);
#endif
    if (robot.urdf != kHrp2)
      continue;
    // The closed form on the same samples, for the time per solve (information only).
    const plantar::walking::Humanoid humanoid(model, plantar::walking::testing::hrp2_description());
    const LegGeometry leg_r = read_leg_geometry(model, humanoid, LegSide::right);
    const LegGeometry leg_l = read_leg_geometry(model, humanoid, LegSide::left);
    std::vector<Eigen::Isometry3d> base_iso, swing_iso;
    for (int i = 0; i <= n_steps; ++i) {
      Eigen::VectorXd qb = q;
      qb.head<7>() = bases[i];
      base_iso.push_back(to_isometry(base_pose(qb)));
      swing_iso.push_back(to_isometry(swing[i]));
    }
    const Eigen::Isometry3d left_iso = to_isometry(left0);
    LegAngles angles_r, angles_l;
    double checksum = 0.0, analytic = 1e30;
    for (int repeat = 0; repeat < 10; ++repeat) {
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i <= n_steps; ++i) {
        solve_leg_ik(leg_r, base_iso[i], swing_iso[i], angles_r);
        solve_leg_ik(leg_l, base_iso[i], left_iso, angles_l);
        checksum += angles_r[3] + angles_l[3];
      }
      analytic = std::min(
          analytic, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::printf("  closed form (solve_leg_ik) on the same samples: %.3f us per solve (best of 10 "
                "runs; checksum %.3f); last sample: max |q_numerical - q_closed_form| = %.3e "
                "rad\n",
                1e6 * analytic / n_solves, checksum,
                std::max((get_leg(model, right, q) - angles_r).cwiseAbs().maxCoeff(),
                         (get_leg(model, left, q) - angles_l).cwiseAbs().maxCoeff()));
    EXPECT_LT((get_leg(model, right, q) - angles_r).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_LT((get_leg(model, left, q) - angles_l).cwiseAbs().maxCoeff(), 1e-8);
  }
}

} // namespace
