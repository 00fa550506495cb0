// The viscoelastic FEM sole (law=prony in Sole/Materials, apps/viscoelastic_sole_foot.h) in the
// humanoid drop scene (scenes/drop.prm, 0.25 s, dt = 1 ms: the landing and the first rebound).
//  - Elastic limits: a branch of zero modulus, and a branch whose tau is 1e9 s (C_eff = C_0 to
//    dt/tau = 1e-12), reproduce the elastic condensed sole of the same instantaneous modulus:
//    waist and contact series to round-off.
//  - Energy balance of each sole: the work of the contact forces on the sole (trapezoid of the
//    step-end forces over the contact displacements) = stored free energy + dissipated energy
//    (each integrated independently at the quadrature points), to the trapezoid's O(dt^2).
//  - ParaView: the sole's .vtu read back with VTK; the integral of dissipated_energy_density
//    over its cells equals the sole's dissipated energy (Float32) and the energy lost in it
//    (work - stored) to the balance's tolerance; the overstress fields are present.
//  - Unsupported combinations: a reduced sole, a Kelvin-Voigt damping time, named.
#include "apps/humanoid_simulation.h"
#include "apps/viscoelastic_sole_foot.h"
#include "coupling/viscoelastic_pad.h"
#include "multibody/kinematics.h"
#include "tests/apps/humanoid_test_utilities.h"
#include "tests/apps/series_test_utilities.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace plantar::app {
namespace {

using testing::series_difference;

/// The SLS rubber of the tests (illustrative): E_inf = 2 MPa, E_1 = 2 MPa at tau = 10 ms.
const char* const sls_rubber = "rubber: law=prony, E=2e6, nu=0.3, E1=2e6, tau1=0.01";

// Output/Write VTU = true keeps the soles' per-cell dissipation (the quadrature form; false: a
// separable sole runs in contact space, fem/viscoelastic_condensation.h). Nothing is written.
Scene drop_scene(const std::string& materials, double time_step = 1e-3, bool write_vtu = false) {
  return testing::load_humanoid_scene("drop", {{"Robot/Foot form", "fem sole"},
                                               {"Simulation/Duration", "0.25"},
                                               {"Simulation/Time step", std::to_string(time_step)},
                                               {"Output/Write CSV", "true"},
                                               {"Output/Write VTU", write_vtu ? "true" : "false"},
                                               {"Sole/Materials", materials}});
}

TEST(ViscoelasticScenes, ElasticLimitsReproduceTheElasticSole) {
  HumanoidSimulation elastic(drop_scene("rubber: law=linear, E=4e6, nu=0.3"));
  elastic.run();
  EXPECT_EQ(dynamic_cast<const ViscoelasticSoleFoot*>(&elastic.foot_model()), nullptr);
  const char* const limits[] = {"rubber: law=prony, E=4e6, nu=0.3, E1=0, tau1=0.01",
                                "rubber: law=prony, E=3e6, nu=0.3, E1=1e6, tau1=1e9"};
  for (const char* materials : limits) {
    HumanoidSimulation visco(drop_scene(materials));
    ASSERT_NE(dynamic_cast<const ViscoelasticSoleFoot*>(&visco.foot_model()), nullptr);
    visco.run();
    const double waist = series_difference(elastic.waist_series(), visco.waist_series());
    const double contacts = series_difference(elastic.contact_series(), visco.contact_series());
    std::printf("%s: waist %.2e, contacts %.2e (relative max differences); peak |a_z| %.6f "
                "vs %.6f m/s^2; dissipated %.3e J\n",
                materials, waist, contacts, visco.summary().max_waist_acceleration_z,
                elastic.summary().max_waist_acceleration_z, visco.summary().sole_dissipated_energy);
    // Round-off of two condensations, through contact solves converged to 1e-8 m/s.
    EXPECT_LT(waist, 1e-7) << materials;
    EXPECT_LT(contacts, 1e-6) << materials;
    EXPECT_LT(visco.summary().sole_dissipated_energy, 1e-9) << materials;
  }
}

struct Balance {
  double work = 0, stored = 0, dissipated = 0;
  double error() const { return std::abs(work - stored - dissipated) / work; }
};

Balance balance(const ViscoelasticSoleFoot& feet, int foot) {
  const fem::ViscoelasticCondensation& sole = feet.sole(foot).sole();
  return {sole.external_work(), sole.stored_energy(), sole.dissipated_energy()};
}

TEST(ViscoelasticScenes, EnergyBalanceAndDissipationField) {
  double previous_error = 0;
  for (const double dt : {1e-3, 5e-4}) {
    HumanoidSimulation simulation(drop_scene(sls_rubber, dt, dt == 1e-3));
    simulation.run();
    const auto& feet = dynamic_cast<const ViscoelasticSoleFoot&>(simulation.foot_model());
    EXPECT_EQ(feet.sole(0).sole().contact_space(), dt != 1e-3);
    double total = 0, error = 0;
    for (int foot = 0; foot < 2; ++foot) {
      const Balance b = balance(feet, foot);
      std::printf("dt = %.1e s, foot %d: work %.6e J, stored %.6e J, dissipated %.6e J, "
                  "balance error %.2e of the work\n",
                  dt, foot, b.work, b.stored, b.dissipated, b.error());
      EXPECT_GT(b.dissipated, 0.05 * b.work);
      EXPECT_LT(b.error(), 2e-2);
      total += b.dissipated;
      error = std::max(error, b.error());
    }
    EXPECT_NEAR(simulation.summary().sole_dissipated_energy, total, 1e-12 * total);
    if (dt < 1e-3) { // O(dt^2): halving dt divides it by about 4
      EXPECT_LT(error, 0.35 * previous_error);
    }
    previous_error = error;

    if (dt < 1e-3)
      continue;
    // The same drop in contact space: the same energies up to the round-off of the contact
    // solves (converged to 1e-8 m/s).
    HumanoidSimulation contact(drop_scene(sls_rubber, dt, false));
    contact.run();
    const auto& contact_feet = dynamic_cast<const ViscoelasticSoleFoot&>(contact.foot_model());
    ASSERT_TRUE(contact_feet.sole(0).sole().contact_space());
    for (int foot = 0; foot < 2; ++foot) {
      const Balance a = balance(contact_feet, foot), b = balance(feet, foot);
      EXPECT_NEAR(a.work, b.work, 1e-7 * b.work);
      EXPECT_NEAR(a.stored, b.stored, 1e-7 * b.work);
      EXPECT_NEAR(a.dissipated, b.dissipated, 1e-7 * b.work);
    }
    // The .vtu of the right sole read back.
    const std::filesystem::path dir = std::filesystem::path(PLANTAR_TEST_WORK) / "visco_vtu";
    std::filesystem::create_directories(dir);
    const std::filesystem::path path = dir / "sole_right.vtu";
    multibody::Data data(simulation.model());
    multibody::forward_kinematics(simulation.model(), data, simulation.q());
    feet.write_fields(0, multibody::frame_placement(simulation.model(), data, feet.sole_frame(0)),
                      path);
    const double integral = testing::vtu_cell_integral(path, "dissipated_energy_density",
                                                       {"overstress_1", "von_mises"});
    const Balance b = balance(feet, 0);
    std::printf("right sole .vtu: int dissipated_energy_density dV = %.6e J; dissipated %.6e "
                "J; work - stored %.6e J\n",
                integral, b.dissipated, b.work - b.stored);
    EXPECT_NEAR(integral, b.dissipated, 1e-5 * b.dissipated); // Float32 fields and points
    EXPECT_NEAR(integral, b.work - b.stored, 2e-2 * b.work);
  }
}

TEST(ViscoelasticScenes, UnsupportedCombinationsAreNamed) {
  Scene reduced = drop_scene(sls_rubber);
  reduced.sole_reduction.patches_x = 2;
  reduced.sole_reduction.patches_y = 2;
  try {
    HumanoidSimulation simulation(reduced);
    ADD_FAILURE() << "a reduced viscoelastic sole was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("Sole/Reduced patches"), std::string::npos) << e.what();
  }
  Scene damped = drop_scene(sls_rubber);
  damped.sole.damping_time = 1e-3;
  try {
    HumanoidSimulation simulation(damped);
    ADD_FAILURE() << "a damped viscoelastic sole was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("Sole/Damping time"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace plantar::app
