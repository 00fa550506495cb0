// Per-time-step functions of plantar_walking allocate nothing: the library sources are compiled
// into this test with EIGEN_RUNTIME_NO_MALLOC (eigen_no_malloc_config.h), and global operator
// new is counted as well.
#include "multibody/walking/joint_reference.h"
#include "multibody/walking/leg_ik.h"
#include "multibody/walking/mass_model.h"
#include "tests/multibody/walking/urdf_fk.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <gtest/gtest.h>
#include <new>

namespace {
std::atomic<long> g_news{0};
} // namespace

void* operator new(std::size_t size) {
  ++g_news;
  if (void* p = std::malloc(size ? size : 1))
    return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace {

using namespace plantar::walking;

const std::string kUrdf = std::string(PLANTAR_SOURCE_DIR) + "/models/hrp2/hrp2.urdf";

TEST(NoMalloc, GuardIsActive) {
  // The guard must fire on a dynamic allocation, otherwise the other tests prove nothing.
  Eigen::internal::set_is_malloc_allowed(false);
  bool fired = false;
  try {
    Eigen::VectorXd v(100);
    v.setZero();
  } catch (const std::runtime_error&) {
    fired = true;
  }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(fired);
}

TEST(NoMalloc, LegIkComAndSample) {
  const auto model = load_urdf(kUrdf);
  const LegGeometry leg = read_leg_geometry(*model, LegSide::left);
  const MassModel mass_model = make_mass_model(*model);
  MassModelData mass_data(mass_model);
  JointReference ref;
  ref.resize(3, 0.005);
  RobotAngles q = RobotAngles::Constant(0.1);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  for (int k = 0; k < 3; ++k)
    ref.set(k, base, (k + 1) * q, Eigen::Vector3d::Zero());
  LegAngles leg_q;
  leg_q << 0.1, 0.05, -0.4, 0.8, -0.4, -0.05;
  base.translation() = Eigen::Vector3d(0.1, 0.0, 0.65);
  Eigen::Isometry3d sole, sampled_base;
  LegAngles solved;
  RobotAngles sampled;
  Eigen::Vector3d com;

  const long news_before = g_news.load();
  Eigen::internal::set_is_malloc_allowed(false);
  sole = leg_forward_kinematics(leg, base, leg_q);
  solve_leg_ik(leg, base, sole, solved);
  com = centre_of_mass(mass_model, mass_data, base, q);
  ref.sample(0.0075, sampled, sampled_base);
  Eigen::internal::set_is_malloc_allowed(true);
  const long news = g_news.load() - news_before;

  // The results are right too (against the URDF chain and linear interpolation).
  std::map<std::string, double> named;
  for (int i = 0; i < n_robot_joints; ++i)
    named[robot_joint_names()[i]] = q(i);
  const auto [mass, com_urdf] = plantar::walking::testing::mass_and_com(*model, named);
  std::printf("operator new calls: %ld; IK error %.2e rad; CoM vs URDF chain %.2e m; sample "
              "error %.2e\n",
              news, (solved - leg_q).cwiseAbs().maxCoeff(), (com - base * com_urdf).norm(),
              (sampled - 2.5 * q).cwiseAbs().maxCoeff());
  EXPECT_EQ(news, 0);
  EXPECT_LT((solved - leg_q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((com - base * com_urdf).norm(), 1e-12);
  EXPECT_LT((sampled - 2.5 * q).cwiseAbs().maxCoeff(), 1e-12);
}

} // namespace
