// Viscoelastic deformable pads (law=prony in Pad N/Materials, apps/pad_set.h) in the humanoid
// kneeling drop (scenes/kneel_drop.prm, 0.25 s at dt = 1 ms: HRP-2 dropped 2 cm onto two knee
// pads, the landing and the first rebound).
//  - Elastic limits: a branch of zero modulus, and a branch whose tau is 1e9 s (C_eff = C_0 to
//    dt/tau = 1e-12), reproduce the elastic pads of the same instantaneous modulus: the
//    sagittal waist motion and the pad forces to round-off, no energy dissipated.
//  - Energy balance of each pad: the work of the contact forces on the pad (trapezoid of the
//    step-end forces over the contact displacements) = stored free energy + dissipated energy
//    (each integrated independently at the quadrature points), to the trapezoid's O(dt^2):
//    halving dt divides the balance error by about 4.
//  - ParaView: the pad's .vtu read back with VTK; the integral of dissipated_energy_density
//    over its cells equals the pad's dissipated energy.
//  - Without the .vtu series the pads run in contact space: the same drop (waist, pad energies)
//    as the quadrature form's, to round-off.
//  - A Kelvin-Voigt damping time on a viscoelastic pad is refused, named.
#include "apps/humanoid_simulation.h"
#include "multibody/kinematics.h"
#include "tests/apps/humanoid_test_utilities.h"
#include "tests/apps/series_test_utilities.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace plantar::app {
namespace {

using testing::series_difference;

/// An SLS pad rubber (illustrative): E_inf = 1 MPa, E_1 = 1 MPa at tau = 10 ms.
const char* const sls_pad = "pad: law=prony, E=1e6, nu=0.3, E1=1e6, tau1=0.01";

Scene kneel_scene(const std::string& materials, double time_step = 1e-3, bool write_vtu = false) {
  return testing::load_humanoid_scene("kneel_drop",
                                      {{"Simulation/Duration", "0.25"},
                                       {"Simulation/Time step", std::to_string(time_step)},
                                       {"Output/Write CSV", "true"},
                                       {"Output/Write VTU", write_vtu ? "true" : "false"},
                                       {"Pad 1/Materials", materials},
                                       {"Pad 1/Damping time", "0"},
                                       {"Pad 2/Materials", materials},
                                       {"Pad 2/Damping time", "0"}});
}

TEST(ViscoelasticPads, ElasticLimitsReproduceTheElasticPads) {
  HumanoidSimulation elastic(kneel_scene("pad: law=linear, E=2e6, nu=0.3"));
  elastic.run();
  ASSERT_EQ(elastic.pads().size(), 2);
  EXPECT_NE(elastic.pads().elastic(0), nullptr);
  EXPECT_GT(elastic.summary().max_pad_force, 100.0); // the robot lands on its pads
  const char* const limits[] = {"pad: law=prony, E=2e6, nu=0.3, E1=0, tau1=0.01",
                                "pad: law=prony, E=1.5e6, nu=0.3, E1=0.5e6, tau1=1e9"};
  for (const char* materials : limits) {
    HumanoidSimulation visco(kneel_scene(materials));
    ASSERT_NE(visco.pads().viscoelastic(0), nullptr);
    ASSERT_NE(visco.pads().viscoelastic(1), nullptr);
    visco.run();
    // The sagittal waist motion and the pad forces (roll, yaw, y and the solver's residual are
    // round-off in this mirror-symmetric drop: no relative scale).
    std::string waist_column, contact_column;
    const double waist = series_difference(elastic.waist_series(), visco.waist_series(),
                                           &waist_column, {"x", "z", "vx", "vz", "pitch"});
    const double contacts =
        series_difference(elastic.contact_series(), visco.contact_series(), &contact_column,
                          {"right_knee_fx", "right_knee_fz", "right_knee_compression",
                           "left_knee_fx", "left_knee_fz", "left_knee_compression"});
    std::printf("%s: waist %.2e (%s), contacts %.2e (%s) (relative max differences); peak pad "
                "force %.3f vs %.3f N; dissipated %.3e J\n",
                materials, waist, waist_column.c_str(), contacts, contact_column.c_str(),
                visco.summary().max_pad_force, elastic.summary().max_pad_force,
                visco.summary().pad_dissipated_energy);
    // Round-off of two condensations, through contact solves converged to 1e-8 m/s.
    EXPECT_LT(waist, 1e-7) << materials;
    EXPECT_LT(contacts, 1e-6) << materials;
    EXPECT_LT(visco.summary().pad_dissipated_energy, 1e-9) << materials;
  }
}

struct Balance {
  double work = 0, stored = 0, dissipated = 0;
  double error() const { return std::abs(work - stored - dissipated) / work; }
};

TEST(ViscoelasticPads, EnergyBalanceAndDissipationField) {
  double previous_error = 0;
  for (const double dt : {1e-3, 5e-4}) {
    // With the ParaView series (dt 1 ms) the pads keep the per-cell dissipation (the quadrature
    // form); without it they run in contact space.
    HumanoidSimulation simulation(kneel_scene(sls_pad, dt, dt == 1e-3));
    simulation.run();
    const PadSet& pads = simulation.pads();
    EXPECT_EQ(pads.viscoelastic(0)->sole().contact_space(), dt != 1e-3);
    double total = 0, error = 0;
    for (int i = 0; i < pads.size(); ++i) {
      const fem::ViscoelasticCondensation& pad = pads.viscoelastic(i)->sole();
      const Balance b{pad.external_work(), pad.stored_energy(), pad.dissipated_energy()};
      std::printf("dt = %.1e s, %s: work %.6e J, stored %.6e J, dissipated %.6e J, balance "
                  "error %.2e of the work\n",
                  dt, pads.name(i).c_str(), b.work, b.stored, b.dissipated, b.error());
      EXPECT_GT(b.dissipated, 0.05 * b.work);
      EXPECT_LT(b.error(), 2e-2);
      total += b.dissipated;
      error = std::max(error, b.error());
    }
    EXPECT_NEAR(simulation.summary().pad_dissipated_energy, total, 1e-12 * total);
    if (dt < 1e-3) { // O(dt^2): halving dt divides it by about 4
      EXPECT_LT(error, 0.35 * previous_error);
    }
    previous_error = error;

    if (dt < 1e-3)
      continue;
    // The .vtu of the right pad read back.
    const std::filesystem::path dir = std::filesystem::path(PLANTAR_TEST_WORK) / "visco_pad_vtu";
    std::filesystem::create_directories(dir);
    const std::filesystem::path path = dir / "pad_right_knee.vtu";
    multibody::Data data(simulation.model());
    multibody::forward_kinematics(simulation.model(), data, simulation.q());
    pads.write_fields(0, data, path);
    const double integral =
        testing::vtu_cell_integral(path, "dissipated_energy_density", {"overstress_1", "strain"});
    const double dissipated = pads.viscoelastic(0)->sole().dissipated_energy();
    std::printf("right pad .vtu: int dissipated_energy_density dV = %.6e J; dissipated %.6e J\n",
                integral, dissipated);
    EXPECT_NEAR(integral, dissipated, 1e-5 * dissipated); // Float32 fields and points
  }
}

TEST(ViscoelasticPads, ContactSpacePadsEqualTheQuadratureForm) {
  // The kneeling drop on SLS pads with and without the .vtu series: the pads run in contact
  // space without it, and the drop is the same to round-off.
  HumanoidSimulation quadrature(kneel_scene(sls_pad, 1e-3, true));
  HumanoidSimulation contact(kneel_scene(sls_pad, 1e-3, false));
  ASSERT_FALSE(quadrature.pads().viscoelastic(0)->sole().contact_space());
  ASSERT_TRUE(contact.pads().viscoelastic(0)->sole().contact_space());
  quadrature.run();
  contact.run();
  std::string waist_column;
  const double waist = series_difference(quadrature.waist_series(), contact.waist_series(),
                                         &waist_column, {"x", "z", "vx", "vz", "pitch"});
  double worst = 0;
  for (int i = 0; i < 2; ++i) {
    const fem::ViscoelasticCondensation& a = quadrature.pads().viscoelastic(i)->sole();
    const fem::ViscoelasticCondensation& b = contact.pads().viscoelastic(i)->sole();
    worst = std::max(
        {worst, std::abs(a.dissipated_energy() - b.dissipated_energy()) / a.dissipated_energy(),
         std::abs(a.external_work() - b.external_work()) / a.external_work(),
         std::abs(a.stored_energy() - b.stored_energy()) / a.external_work()});
  }
  std::printf("contact space vs quadrature form: waist %.2e (%s), pad energies %.2e (relative)\n",
              waist, waist_column.c_str(), worst);
  // The same arithmetic up to round-off (measured 4e-15 and 3.5e-14).
  EXPECT_LT(waist, 1e-10);
  EXPECT_LT(worst, 1e-10);
}

TEST(ViscoelasticPads, KelvinVoigtDampingIsRefused) {
  try {
    testing::load_humanoid_scene("kneel_drop", {{"Pad 1/Materials", sls_pad}});
    ADD_FAILURE() << "a damped viscoelastic pad was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("Pad 1/Damping time = 0.002"), std::string::npos) << message;
    EXPECT_NE(message.find("allowed 0"), std::string::npos) << message;
  }
}

} // namespace
} // namespace plantar::app
