// The summary's single-support CoP margin (issue 23: what a sole costs in balance) on the
// default walk's first stances (4 s), rigid feet and FEM soles, against the same figure
// computed here from the feet's ground forces and the planned footsteps (the stance sole taken
// at the placement nearest to its CoP at the stance's first sample: the closed form
// min(L/2 - |dx|, W/2 - |dy|) of a level rectangle), within the soles' distance from their plans
// (1 mm).
#include "apps/humanoid_simulation.h"
#include "tests/apps/humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace plantar::app {
namespace {

void check_balance_figures(const std::string& form) {
  const Scene scene = testing::load_humanoid_scene("default", {{"Robot/Foot form", form},
                                                               {"Robot/Foot forms", ""},
                                                               {"Simulation/Duration", "4"},
                                                               {"Output/Write VTU", "false"}});
  HumanoidSimulation simulation(scene);
  // Every planned placement of a sole (the initial ones and the footsteps).
  const walking::WalkingParameters& walk = scene.walking.walk;
  std::vector<walking::Footstep> placements = {walk.initial_right, walk.initial_left};
  placements.insert(placements.end(), walk.footsteps.begin(), walk.footsteps.end());
  const double half_length = 0.5 * scene.sole.length, half_width = 0.5 * scene.sole.width;
  const double weight = simulation.summary().robot_mass * simulation.model().gravity.norm();
  const double dt = scene.simulation.time_step;
  double since[2] = {-1, -1}, margin = std::numeric_limits<double>::infinity();
  int on[2] = {-1, -1}; ///< each stance's placement
  simulation.run([&](const HumanoidSimulation& s) {
    const double t = s.time();
    for (int foot = 0; foot < 2; ++foot) {
      if (!(s.foot_report(foot).force.z() > 1.0)) {
        since[foot] = -1;
        on[foot] = -1;
      } else if (since[foot] < 0)
        since[foot] = t;
    }
    if ((since[0] >= 0) == (since[1] >= 0))
      return;
    const int stance = since[0] >= 0 ? 0 : 1;
    const FootReport& report = s.foot_report(stance);
    if (!(report.force.z() > 0.1 * weight) ||
        t - since[stance] < scene.output.landing_window - 0.5 * dt)
      return;
    const Eigen::Vector2d cop = report.moment.head<2>() / report.force.z();
    if (on[stance] < 0) { // the stance's first sample: the placement nearest to its CoP
      double nearest = std::numeric_limits<double>::infinity();
      for (int i = 0; i < static_cast<int>(placements.size()); ++i) {
        const double d = std::hypot(cop.x() - placements[i].x, cop.y() - placements[i].y);
        if (d < nearest) {
          nearest = d;
          on[stance] = i;
        }
      }
    }
    const walking::Footstep& p = placements[on[stance]];
    margin = std::min(margin, std::min(half_length - std::abs(cop.x() - p.x),
                                       half_width - std::abs(cop.y() - p.y)));
  });
  const HumanoidSummary& summary = simulation.summary();
  const Eigen::Vector3d right = summary.final_right_sole, left = summary.final_left_sole;
  std::printf("%s: single-support CoP margin %.3f mm (here, from the plan: %.3f mm); soles at "
              "the end (%.4f, %.4f), (%.4f, %.4f) m\n",
              form.c_str(), summary.min_single_support_margin * 1e3, margin * 1e3, right.x(),
              right.y(), left.x(), left.y());
  EXPECT_TRUE(std::isfinite(margin));
  EXPECT_NEAR(summary.min_single_support_margin, margin, 1e-3);
}

TEST(BalanceFigures, SingleSupportMarginRigidFeet) {
  check_balance_figures("rigid");
}
TEST(BalanceFigures, SingleSupportMarginFemSole) {
  check_balance_figures("fem sole");
}

} // namespace
} // namespace plantar::app
