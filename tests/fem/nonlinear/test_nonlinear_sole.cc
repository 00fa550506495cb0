// The nonlinear sole as seen by the contact coupling (fem/nonlinear_sole.h):
//  - at u = 0 the tangent compliance equals the linear sole's K^-1 contact
//    block computed with the linear solver class (fem/linear_elasticity.h);
//  - static comparison nonlinear vs linear (same E, nu) under increasing
//    contact load: differences shrink linearly as the load decreases;
//  - an increasing load ramp: linearised-prediction error and the number of
//    re-condensations for a tolerance; the re-condensed tangent compliance
//    against finite differences of Newton solutions;
//  - a sole squeezed to 40 % of its thickness converges with J > 0.
#include "fem/field_output.h"
#include "fem/nonlinear_sole.h"
#include "fem_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace plantar::fem {
namespace {

using Formulation = NonlinearSettings::Formulation;
constexpr double L = 0.12, W = 0.06, T = 0.02, E = 4e6;
constexpr dealii::types::boundary_id bottom = 4, top = 5;

void make_sole(dealii::Triangulation<3>& tria, unsigned int n_z = 2) {
  testing::make_box(tria, CellKind::hexahedron, 12, 6, n_z, L, W, T);
}

// Consistent nodal forces of a uniform pressure @p p (Pa) pushing the bottom
// face up (+z), Q1: a quarter of each face's area per vertex.
dealii::Vector<double> pressure_forces(const dealii::Triangulation<3>& tria,
                                       const NonlinearSole& sole, double p) {
  dealii::Vector<double> forces(3 * sole.n_contacts());
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == bottom)
        for (unsigned int v = 0; v < 4; ++v)
          for (unsigned int k = 0; k < sole.n_contacts(); ++k)
            if (sole.contact_positions()[k].distance(cell->face(f)->vertex(v)) < 1e-12)
              forces(3 * k + 2) += p * cell->face(f)->measure() / 4;
  return forces;
}

TEST(NonlinearSole, SmallLoadMatchesLinearSole) {
  dealii::Triangulation<3> tria;
  make_sole(tria);
  const double nu = 0.45;
  const HyperelasticMaterialTable materials(
      std::make_shared<NeoHookeanLaw>(NeoHookeanLaw::from_youngs(E, nu)));
  const Discretization disc(CellKind::hexahedron, 1);
  NonlinearSoleParameters parameters;
  parameters.attached_boundary = top;
  parameters.contact_boundary = bottom;
  const NonlinearSole reference_sole(tria, disc, materials, parameters);

  // Linear sole with the linear solver class: C_lin = [K^-1]_cc.
  const MaterialTable linear_materials = materials.linearized();
  LinearElasticity linear(tria, disc, linear_materials);
  linear.setup({{top, nullptr}});
  linear.assemble();
  linear.solve();
  const unsigned int n = 3 * reference_sole.n_contacts();
  dealii::FullMatrix<double> C_lin(n, n);
  dealii::Vector<double> rhs(linear.dof_handler().n_dofs()), x(rhs.size());
  for (unsigned int j = 0; j < n; ++j) {
    rhs = 0;
    rhs(reference_sole.contact_dofs()[j / 3][j % 3]) = 1;
    linear.solve(rhs, x);
    for (unsigned int i = 0; i < n; ++i)
      C_lin(i, j) = x(reference_sole.contact_dofs()[i / 3][i % 3]);
  }
  double max_diff = 0, max_value = 0;
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int j = 0; j < n; ++j) {
      max_diff = std::max(max_diff, std::abs(C_lin(i, j) - reference_sole.compliance()(i, j)));
      max_value = std::max(max_value, std::abs(C_lin(i, j)));
    }
  std::printf("\n%u contact nodes: max |C_T(0) - C_lin| / max |C_lin| = %.2e (tol 1e-8), "
              "raw asymmetry %.1e\n",
              reference_sole.n_contacts(), max_diff / max_value, reference_sole.raw_asymmetry());
  EXPECT_LT(max_diff / max_value, 1e-8);

  // Force control: contact displacements, nonlinear vs linear (C_lin f).
  std::printf("\nForce control (uniform contact pressure), nonlinear vs linear sole, E = %.1e, "
              "nu = %.2f\n%12s %14s %14s %12s %12s %6s\n",
              E, nu, "p (Pa)", "max u_c NL", "max u_c lin", "rel diff", "diff/p", "Newton");
  std::vector<double> rel;
  const std::vector<double> loads = {1e3, 1e4, 1e5, 4e5};
  for (const double p : loads) {
    NonlinearSole sole(tria, disc, materials, parameters);
    const dealii::Vector<double> forces = pressure_forces(tria, sole, p);
    const SoleUpdateReport report = sole.apply_contact_forces(forces);
    dealii::Vector<double> u_lin(n);
    C_lin.vmult(u_lin, forces);
    dealii::Vector<double> diff(sole.contact_displacements());
    diff -= u_lin;
    const double r = diff.linfty_norm() / u_lin.linfty_norm();
    rel.push_back(r);
    std::printf("%12.1e %14.6e %14.6e %12.3e %12.3e %6u\n", p,
                sole.contact_displacements().linfty_norm(), u_lin.linfty_norm(), r, r / p,
                report.newton.iterations);
  }
  EXPECT_LT(rel[0], 1e-3);
  for (std::size_t i = 1; i < rel.size(); ++i)
    EXPECT_GT(rel[i], rel[i - 1]); // differences shrink as the load decreases
  // First order in the load: diff/p about constant at small loads (within 20 %).
  EXPECT_NEAR((rel[1] / loads[1]) / (rel[0] / loads[0]), 1.0, 0.2);

  // Displacement control (sole pressed by a flat plate): contact force, NL vs linear.
  std::printf("\nDisplacement control (bottom pushed up by d, bonded), total contact force\n"
              "%12s %14s %14s %12s\n",
              "d / t", "F NL (N)", "F lin (N)", "rel diff");
  std::vector<double> rel_force;
  for (const double strain : {1e-4, 1e-3, 1e-2, 0.1}) {
    const dealii::Functions::ConstantFunction<3> plate(std::vector<double>{0, 0, strain * T});
    NonlinearElasticity nl(tria, disc, materials, parameters.newton);
    nl.setup({{top, nullptr, {{true, true, true}}}, {bottom, &plate, {{true, true, true}}}});
    nl.solve(strain > 0.05 ? 4 : 1);
    const double f_nl = nl.reaction_force(bottom)[2];
    nl.solve_linearized();
    const double f_lin = nl.reaction_force(bottom)[2];
    rel_force.push_back(std::abs(f_nl / f_lin - 1));
    std::printf("%12.1e %14.6e %14.6e %12.3e\n", strain, f_nl, f_lin, rel_force.back());
  }
  EXPECT_LT(rel_force[0], 1e-3);
  for (std::size_t i = 1; i < rel_force.size(); ++i)
    EXPECT_GT(rel_force[i], rel_force[i - 1]);
}

TEST(NonlinearSole, RecondensationUnderIncreasingLoad) {
  dealii::Triangulation<3> tria;
  make_sole(tria);
  const HyperelasticMaterialTable materials(
      std::make_shared<NeoHookeanLaw>(NeoHookeanLaw::from_youngs(E, 0.49)));
  const Discretization disc(CellKind::hexahedron, 1);
  NonlinearSoleParameters parameters;
  parameters.attached_boundary = top;
  parameters.contact_boundary = bottom;
  parameters.newton.formulation = Formulation::mixed;
  parameters.recondensation_tolerance = 0.02;
  NonlinearSole sole(tria, disc, materials, parameters);
  NonlinearSole never(tria, disc, materials, [&] {
    auto p = parameters;
    p.recondensation_tolerance = 1e9;
    return p;
  }());

  const unsigned int n_steps = 10;
  const double p_max = 1.5e6;
  std::printf("\nIncreasing contact pressure, Q1-P0 mixed, nu = 0.49, tolerance %.3f\n"
              "%6s %10s %12s %10s %8s %8s %12s\n",
              parameters.recondensation_tolerance, "step", "p (Pa)", "max u_z (m)", "error",
              "recond", "Newton", "err (never)");
  double first_error = 0;
  for (unsigned int s = 1; s <= n_steps; ++s) {
    // Quadratic ramp: small increments first (small strain), larger later.
    const double p = p_max * std::pow(static_cast<double>(s) / n_steps, 2);
    const auto forces = pressure_forces(tria, sole, p);
    const SoleUpdateReport report = sole.update(forces);
    const SoleUpdateReport report_never = never.update(forces);
    if (s == 1)
      first_error = report.prediction_error;
    std::printf("%6u %10.3e %12.4e %10.4f %8s %8u %12.4f\n", s, p,
                sole.contact_displacements().linfty_norm(), report.prediction_error,
                report.recondensed ? "yes" : "no", report.newton.iterations,
                report_never.prediction_error);
    EXPECT_GT(report.newton.min_jacobian, 0);
  }
  std::printf("re-condensations: %u (tolerance %.3f, max tolerated error %.4f); "
              "never re-condensing: max error %.4f\n",
              sole.n_recondensations(), parameters.recondensation_tolerance,
              sole.max_tolerated_error(), never.max_tolerated_error());
  EXPECT_LT(first_error, parameters.recondensation_tolerance); // small strain: linear holds
  EXPECT_GE(sole.n_recondensations(), 1u);
  EXPECT_LT(sole.n_recondensations(), n_steps);
  EXPECT_LE(sole.max_tolerated_error(), parameters.recondensation_tolerance);
  EXPECT_EQ(never.n_recondensations(), 0u);
  EXPECT_GT(never.max_tolerated_error(), parameters.recondensation_tolerance);

  // The re-condensed tangent compliance at the deformed state against finite
  // differences of Newton solutions (a few columns).
  sole.condense();
  const dealii::Vector<double> base_force = sole.contact_forces();
  const dealii::Vector<double> base_u = sole.contact_displacements();
  const unsigned int n = 3 * sole.n_contacts();
  double max_error = 0, max_value = 0;
  for (const unsigned int j : {2u, n / 2 + 2, n - 1, n / 3}) {
    const double h = 1e-3 * base_force.linfty_norm();
    dealii::Vector<double> plus = base_force, minus = base_force;
    plus(j) += h;
    minus(j) -= h;
    sole.apply_contact_forces(plus);
    const dealii::Vector<double> u_plus = sole.contact_displacements();
    sole.apply_contact_forces(minus);
    const dealii::Vector<double> u_minus = sole.contact_displacements();
    for (unsigned int i = 0; i < n; ++i) {
      const double fd = (u_plus(i) - u_minus(i)) / (2 * h);
      max_error = std::max(max_error, std::abs(fd - sole.compliance()(i, j)));
      max_value = std::max(max_value, std::abs(sole.compliance()(i, j)));
    }
    sole.apply_contact_forces(base_force);
  }
  std::printf("tangent compliance at p = %.2e Pa vs central differences of Newton solutions: "
              "max rel error %.2e (tol 1e-4)\n",
              p_max, max_error / max_value);
  EXPECT_LT(max_error / max_value, 1e-4);
}

TEST(NonlinearSole, SqueezedTo40PercentKeepsPositiveJacobian) {
  dealii::Triangulation<3> tria;
  make_sole(tria, 4);
  const HyperelasticMaterialTable materials(
      std::make_shared<NeoHookeanLaw>(NeoHookeanLaw::from_youngs(E, 0.45)));
  const Discretization disc(CellKind::hexahedron, 1);
  NonlinearSettings settings;
  settings.formulation = Formulation::mixed;
  NonlinearElasticity problem(tria, disc, materials, settings);
  // Top attached, bottom pushed up by 0.6 t on a frictionless plate (u_x, u_y free).
  const dealii::Functions::ConstantFunction<3> plate(std::vector<double>{0, 0, 0.6 * T});
  problem.setup({{top, nullptr, {{true, true, true}}}, {bottom, &plate, {{false, false, true}}}});
  // Rigid motion along x, y: fixed by the attached top.
  const unsigned int n_steps = 12;
  std::printf("\nSole squeezed to 40 %% of its thickness (bonded top, frictionless plate), "
              "Q1-P0 mixed, nu = 0.45\n%6s %10s %10s %12s %10s\n",
              "step", "d / t", "Newton", "force (N)", "min J");
  unsigned int total = 0;
  for (unsigned int s = 1; s <= n_steps; ++s) {
    const NewtonReport report = problem.solve_at(static_cast<double>(s) / n_steps);
    total += report.iterations;
    std::printf("%6u %10.3f %10u %12.4e %10.4f\n", s, 0.6 * s / n_steps, report.iterations,
                problem.reaction_force(bottom)[2], report.min_jacobian);
    EXPECT_GT(report.min_jacobian, 0);
    EXPECT_LE(report.iterations, settings.max_iterations);
  }
  std::printf("total Newton iterations %u, min J %.4f\n", total, problem.min_jacobian());
  EXPECT_GT(problem.min_jacobian(), 0);
  // Per-cell det F of the output agrees with the solver's minimum; the field is written.
  const dealii::Vector<float> cell_j = cell_min_jacobian(problem);
  double min_cell_j = 1e300;
  for (const float j : cell_j)
    min_cell_j = std::min(min_cell_j, static_cast<double>(j));
  std::printf("output: min det F over cells %.6f (solver %.6f)\n", min_cell_j,
              problem.min_jacobian());
  EXPECT_NEAR(min_cell_j, problem.min_jacobian(), 1e-6);
  const auto path = std::filesystem::current_path() / "squeezed_sole.vtu";
  write_vtu(problem, path);
  EXPECT_GT(std::filesystem::file_size(path), 1000u);
  // Thickness check: the bottom moved by 0.6 t (to 40 % of the thickness).
  EXPECT_NEAR(problem.displacement_at(dealii::Point<3>(L / 2, W / 2, 0))[2], 0.6 * T, 1e-12);
}

} // namespace
} // namespace plantar::fem

namespace plantar::fem {
namespace {

TEST(NonlinearSole, BadInput) {
  dealii::Triangulation<3> tria;
  testing::make_box(tria, CellKind::hexahedron, 2, 2, 1, 0.1, 0.05, 0.02);
  const HyperelasticMaterialTable materials(
      std::make_shared<NeoHookeanLaw>(NeoHookeanLaw::from_youngs(4e6, 0.45)));
  const Discretization disc(CellKind::hexahedron, 1);
  auto expect_message = [](auto&& make, const std::string& fragment) {
    try {
      make();
      ADD_FAILURE() << "no exception, expected '" << fragment << "'";
    } catch (const std::exception& e) {
      std::printf("bad input -> %s\n", e.what());
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  NonlinearSoleParameters parameters;
  parameters.attached_boundary = 5;
  parameters.contact_boundary = 4;
  auto bad = parameters;
  bad.recondensation_tolerance = -1;
  expect_message([&] { NonlinearSole(tria, disc, materials, bad); }, "recondensation_tolerance");
  bad = parameters;
  bad.newton.residual_tolerance = 2;
  expect_message([&] { NonlinearSole(tria, disc, materials, bad); }, "residual_tolerance");
  bad = parameters;
  bad.contact_boundary = 9;
  expect_message([&] { NonlinearSole(tria, disc, materials, bad); }, "boundary id 9");
  NonlinearSole sole(tria, disc, materials, parameters);
  expect_message([&] { sole.apply_contact_forces(dealii::Vector<double>(5)); }, "expected 3 n_c");
  // A force that inverts the sole: Newton fails, the state is restored.
  dealii::Vector<double> crush(3 * sole.n_contacts());
  for (unsigned int k = 0; k < sole.n_contacts(); ++k)
    crush(3 * k + 2) = 1e9;
  expect_message([&] { sole.apply_contact_forces(crush); }, "not reached");
  EXPECT_EQ(sole.elasticity().solution().linfty_norm(), 0.0);
}

} // namespace
} // namespace plantar::fem
