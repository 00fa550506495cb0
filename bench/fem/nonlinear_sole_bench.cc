// Nonlinear sole benchmark (prints tables; never passes or fails on time).
// Sole box 0.12 x 0.06 x 0.02 m, Neo-Hookean E = 4 MPa, nu = 0.45, Q1-P0
// mixed, top attached, uniform contact pressure on the bottom.
//  1. Newton solve time and iterations against load level and mesh size,
//     with the max contact displacement's error against the finest mesh.
//  2. Tangent condensation (3 n_c solves) time against mesh size.
//  3. Linear vs nonlinear cost of a load ramp: re-condensations and time
//     against the re-condensation tolerance.
#include "fem/nonlinear_sole.h"

#include <deal.II/grid/grid_generator.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

using namespace plantar::fem;

namespace {

constexpr double L = 0.12, W = 0.06, T = 0.02;

void make_sole(dealii::Triangulation<3>& tria, unsigned int refinement) {
  dealii::GridGenerator::subdivided_hyper_rectangle(
      tria, {6 * refinement, 3 * refinement, refinement}, dealii::Point<3>(0, 0, 0),
      dealii::Point<3>(L, W, T), true);
}

dealii::Vector<double> pressure_forces(const dealii::Triangulation<3>& tria,
                                       const NonlinearSole& sole, double p) {
  dealii::Vector<double> forces(3 * sole.n_contacts());
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == 4)
        for (unsigned int v = 0; v < 4; ++v)
          for (unsigned int k = 0; k < sole.n_contacts(); ++k)
            if (sole.contact_positions()[k].distance(cell->face(f)->vertex(v)) < 1e-12)
              forces(3 * k + 2) += p * cell->face(f)->measure() / 4;
  return forces;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

int main() {
  const HyperelasticMaterialTable materials(
      std::make_shared<NeoHookeanLaw>(NeoHookeanLaw::from_youngs(4e6, 0.45)));
  const Discretization disc(CellKind::hexahedron, 1);
  NonlinearSoleParameters parameters;
  parameters.attached_boundary = 5;
  parameters.contact_boundary = 4;
  parameters.newton.formulation = NonlinearSettings::Formulation::mixed;

  const std::vector<unsigned int> refinements = {1, 2, 3, 4};
  const std::vector<double> loads = {1e4, 1e5, 5e5};
  // results[r][l] = max contact u_z
  std::vector<std::vector<double>> u(refinements.size(), std::vector<double>(loads.size()));
  std::vector<std::vector<double>> newton_time(u), iterations(u);
  std::vector<double> condense_time(refinements.size());
  std::vector<unsigned int> n_dofs(refinements.size()), n_contacts(refinements.size());
  for (std::size_t r = 0; r < refinements.size(); ++r) {
    dealii::Triangulation<3> tria;
    make_sole(tria, refinements[r]);
    for (std::size_t l = 0; l < loads.size(); ++l) {
      auto start = std::chrono::steady_clock::now();
      NonlinearSole sole(tria, disc, materials, parameters);
      if (l == 0) {
        condense_time[r] = seconds_since(start);
        n_dofs[r] = sole.elasticity().dof_handler().n_dofs();
        n_contacts[r] = sole.n_contacts();
      }
      const auto forces = pressure_forces(tria, sole, loads[l]);
      start = std::chrono::steady_clock::now();
      const SoleUpdateReport report = sole.apply_contact_forces(forces);
      newton_time[r][l] = seconds_since(start);
      iterations[r][l] = report.newton.iterations;
      double max_uz = 0;
      for (unsigned int k = 0; k < sole.n_contacts(); ++k)
        max_uz = std::max(max_uz, sole.contact_displacements()(3 * k + 2));
      u[r][l] = max_uz;
    }
  }
  std::printf("Newton solve of the contact load (Q1-P0 mixed, E = 4 MPa, nu = 0.45)\n");
  std::printf("%6s %8s %6s %10s %8s %10s %12s %12s\n", "refine", "dofs", "n_c", "p (Pa)", "Newton",
              "time (s)", "max u_z (m)", "err vs fine");
  for (std::size_t r = 0; r < refinements.size(); ++r)
    for (std::size_t l = 0; l < loads.size(); ++l)
      std::printf("%6u %8u %6u %10.1e %8.0f %10.4f %12.5e %12.2e\n", refinements[r], n_dofs[r],
                  n_contacts[r], loads[l], iterations[r][l], newton_time[r][l], u[r][l],
                  std::abs(u[r][l] / u.back()[l] - 1));
  std::printf("\nConstruction = setup + tangent condensation at u = 0 (3 n_c solves)\n");
  std::printf("%6s %8s %6s %12s\n", "refine", "dofs", "n_c", "time (s)");
  for (std::size_t r = 0; r < refinements.size(); ++r)
    std::printf("%6u %8u %6u %12.4f\n", refinements[r], n_dofs[r], n_contacts[r], condense_time[r]);

  // Ramp with re-condensation: cost against tolerance.
  std::printf("\nLoad ramp 0 -> 1 MPa in 20 steps (refine 2): re-condensations and time\n");
  std::printf("%12s %10s %14s %12s\n", "tolerance", "recond", "max tolerated", "time (s)");
  dealii::Triangulation<3> tria;
  make_sole(tria, 2);
  for (const double tolerance : {1e9, 0.2, 0.05, 0.01, 0.002}) {
    auto p = parameters;
    p.recondensation_tolerance = tolerance;
    NonlinearSole sole(tria, disc, materials, p);
    const auto start = std::chrono::steady_clock::now();
    for (unsigned int s = 1; s <= 20; ++s)
      sole.update(pressure_forces(tria, sole, 1e6 * s / 20.0));
    std::printf("%12.3g %10u %14.4f %12.3f\n", tolerance, sole.n_recondensations(),
                sole.max_tolerated_error(), seconds_since(start));
  }
  return 0;
}
