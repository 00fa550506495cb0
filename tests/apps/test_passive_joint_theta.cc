// The compliant ankle's springs at their own theta (Simulation/Passive joint theta, issue 23):
// on the default comparison's setting (scenes/default.prm: dt 0.5 ms, theta 1/2, stabilizer)
// the compliant-ankle robot standing then starting to walk (1.2 s):
// - standing, the ground force equals the weight (1 %) in every setting;
// - with the ankle springs at theta 1/2 it rings at the step's frequency: its change from one
//   step to the next exceeds 10 % of the weight;
// - at passive theta 1 (the default) that change is under 0.1 % of the weight, as for the
//   rigid feet and for the whole robot at theta 1 (the ringing is the trapezoidal rule's);
// - the compliant joints' dofs follow passive theta, the rest theta (multibody unit test
//   multibody_stepper_theta_test checks the scheme itself against a dense computation);
// - with the foot damping of the ankle springs' tilt stiffness (Control/Foot damping rate 12 /s:
//   D = 50 N m s/rad) the explicit admittance rings at the step's frequency on raw F/T
//   readings; read through a 25 Hz low-pass (Control/Force sensor bandwidth) the change is
//   again under 0.1 % of the weight.
#include "apps/humanoid_simulation.h"
#include "tests/apps/humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace plantar::app {
namespace {

struct Ringing {
  double rms_change; ///< N: RMS of the step-to-step change of the total vertical ground force
  double mean;       ///< N: its mean
  double weight;     ///< N: the robot's weight
};

/// Over t in [0.2, 1.2] s, while the robot stands (the first step starts at 1.6 s).
Ringing force_ringing(const std::string& form, const std::string& theta,
                      const std::string& passive_theta, const std::string& rate = "0",
                      const std::string& bandwidth = "0") {
  const Scene scene =
      testing::load_humanoid_scene("default", {{"Robot/Foot form", form},
                                               {"Robot/Foot forms", ""},
                                               {"Simulation/Theta", theta},
                                               {"Simulation/Passive joint theta", passive_theta},
                                               {"Control/Foot damping rate", rate},
                                               {"Control/Force sensor bandwidth", bandwidth},
                                               {"Simulation/Duration", "1.2"},
                                               {"Output/Write VTU", "false"}});
  HumanoidSimulation simulation(scene);
  double previous = 0.0, sum = 0.0, total = 0.0;
  int n = 0;
  simulation.run([&](const HumanoidSimulation& s) {
    const double f = s.foot_report(0).force.z() + s.foot_report(1).force.z();
    if (s.time() > 0.2 + 1e-9) {
      sum += (f - previous) * (f - previous);
      total += f;
      ++n;
    }
    previous = f;
  });
  const Ringing r{std::sqrt(sum / n), total / n,
                  simulation.summary().robot_mass * simulation.model().gravity.norm()};
  std::printf("%s, theta %s, passive theta %s, foot damping rate %s /s, F/T bandwidth %s Hz: "
              "F_z mean %.2f N (weight %.2f N), rms change from step to step %.3g N\n",
              form.c_str(), theta.c_str(), passive_theta.c_str(), rate.c_str(), bandwidth.c_str(),
              r.mean, r.weight, r.rms_change);
  return r;
}

// Standing, the ground force equals the weight and changes slowly: the step-to-step change is
// a small fraction of the weight unless the scheme rings.
TEST(PassiveJointTheta, AnkleSpringsAtBackwardEulerDoNotRingOnTheDefaultSetting) {
  const Ringing rigid = force_ringing("rigid", "0.5", "1");
  const Ringing trapezoidal = force_ringing("compliant ankle", "0.5", "0.5");
  const Ringing backward = force_ringing("compliant ankle", "0.5", "1");
  const Ringing all_backward = force_ringing("compliant ankle", "1", "1");
  for (const Ringing& r : {rigid, trapezoidal, backward, all_backward})
    EXPECT_NEAR(r.mean, r.weight, 0.01 * r.weight);
  EXPECT_GT(trapezoidal.rms_change, 0.1 * trapezoidal.weight);
  for (const Ringing& r : {rigid, backward, all_backward})
    EXPECT_LT(r.rms_change, 1e-3 * r.weight);
}

// The admittance D theta' = tau_d - tau, explicit at dt, moves the ankle's reference; the servo's
// damping k_d acts on the reference's finite-difference velocity, so at the step's frequency a
// change a of the reference is a torque of about 2 k_d a / dt and the loop gain is of order
// 2 k_d / D times the part of that torque the ground takes through the light ankle link and its
// springs: 25 times that part at k_d = 630, D = 50 N m s/rad (rigid feet: D = 8300, 0.15). The
// sensor's low-pass divides it by alpha / (2 - alpha) = 1 / 25 at 25 Hz and dt 0.5 ms.
TEST(PassiveJointTheta, FastFootAdmittanceWantsTheForceSensorsBandwidth) {
  const Ringing raw = force_ringing("compliant ankle", "0.5", "1", "12", "0");
  const Ringing filtered = force_ringing("compliant ankle", "0.5", "1", "12", "25");
  EXPECT_GT(raw.rms_change, 0.1 * raw.weight);
  EXPECT_NEAR(filtered.mean, filtered.weight, 0.01 * filtered.weight);
  EXPECT_LT(filtered.rms_change, 1e-3 * filtered.weight);
}

} // namespace
} // namespace plantar::app
