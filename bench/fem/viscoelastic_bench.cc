// Viscoelastic sole benchmark (prints a table; never passes or fails on time).
// Sole box 0.12 x 0.06 x 0.02 m, top attached, two regions relaxing differently (heel: E_inf =
// 2 MPa, nu = 0.45, E_1 = 3 MPa tau 1 ms, E_2 = 1 MPa tau 50 ms; fore: G_inf = 0.5 MPa,
// K_inf = 5 MPa, G_1 = 1 MPa tau 20 ms shear only, G_2 = 0.3 MPa K_2 = 1 MPa tau 0.3 s),
// dt = 1 ms, a varying contact load. Per mesh: set-up (assembly, LU of K_eff, the 3 n_c
// unit-load solves of C_eff), and per step the field solve (K_eff u = P f - f_h), the history
// update (internal variables, f_h, d: cell loop + one back-substitution) against one dense
// product C_eff f (the order of one contact-solver sweep's work on this patch).
// Second table: a separable sole (both regions with the heel's spectrum shape: fore E_inf =
// 5 MPa, nu = 0.3, E_1 = 7.5 MPa tau 1 ms, E_2 = 2.5 MPa tau 50 ms), its quadrature form
// (field solve + history) against its contact-space form (ViscoelasticCondensationParameters::
// cell_dissipation = false), per step, and the largest difference of u_c over the steps.
#include "fem/viscoelastic_condensation.h"

#include <deal.II/grid/grid_generator.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace plantar::fem;

namespace {

constexpr double L = 0.12, W = 0.06, T = 0.02;

std::map<dealii::types::material_id, ViscoelasticMaterial> materials() {
  const double nu = 0.45;
  auto g = [nu](double e) { return e / (2 * (1 + nu)); };
  auto k = [nu](double e) { return e / (3 * (1 - 2 * nu)); };
  std::map<dealii::types::material_id, ViscoelasticMaterial> m;
  m.emplace(0, ViscoelasticMaterial(g(2e6), k(2e6),
                                    {{g(3e6), k(3e6), 1e-3}, {g(1e6), k(1e6), 5e-2}}, "heel"));
  m.emplace(1, ViscoelasticMaterial(0.5e6, 5e6, {{1e6, 0.0, 2e-2}, {0.3e6, 1e6, 0.3}}, "fore"));
  return m;
}

std::map<dealii::types::material_id, ViscoelasticMaterial> separable_materials() {
  auto prony = [](double E, double nu, const char* name) {
    auto g = [nu](double e) { return e / (2 * (1 + nu)); };
    auto k = [nu](double e) { return e / (3 * (1 - 2 * nu)); };
    return ViscoelasticMaterial(
        g(E), k(E), {{g(1.5 * E), k(1.5 * E), 1e-3}, {g(0.5 * E), k(0.5 * E), 5e-2}}, name);
  };
  std::map<dealii::types::material_id, ViscoelasticMaterial> m;
  m.emplace(0, prony(2e6, 0.45, "heel"));
  m.emplace(1, prony(5e6, 0.3, "fore"));
  return m;
}

void make_box(CellKind kind, unsigned int refinement, dealii::Triangulation<3>& tria) {
  const std::vector<unsigned int> cells{6 * refinement, 3 * refinement, refinement};
  if (kind == CellKind::hexahedron)
    dealii::GridGenerator::subdivided_hyper_rectangle(tria, cells, dealii::Point<3>(0, 0, 0),
                                                      dealii::Point<3>(L, W, T), true);
  else {
    dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(
        tria, cells, dealii::Point<3>(0, 0, 0), dealii::Point<3>(L, W, T));
    for (const auto& cell : tria.active_cell_iterators())
      for (const auto& face : cell->face_iterators())
        if (face->at_boundary() && std::abs(face->center()[2]) < 1e-12)
          face->set_boundary_id(4);
        else if (face->at_boundary() && std::abs(face->center()[2] - T) < 1e-12)
          face->set_boundary_id(5);
        else if (face->at_boundary())
          face->set_boundary_id(0);
  }
  for (const auto& cell : tria.active_cell_iterators())
    cell->set_material_id(cell->center()[0] < L / 3 ? 0 : 1);
}

// Top attached (id 5), bottom in contact (id 4), dt = 1 ms.
ViscoelasticCondensationParameters bench_parameters() {
  ViscoelasticCondensationParameters parameters;
  parameters.attached_boundary = 5;
  parameters.contact_boundary = 4;
  parameters.time_step = 1e-3;
  return parameters;
}

void load_at(double t, unsigned int n_contacts, dealii::Vector<double>& f) {
  for (unsigned int k = 0; k < n_contacts; ++k)
    f(3 * k + 2) = -2.0 * (1 - std::cos(2 * M_PI * 5 * t)) * (1 + 0.01 * k);
}

void run(CellKind kind, unsigned int degree, unsigned int refinement) {
  dealii::Triangulation<3> tria;
  make_box(kind, refinement, tria);
  const std::vector<unsigned int> cells{6 * refinement, 3 * refinement, refinement};
  const Discretization disc(kind, degree);
  const ViscoelasticMaterialTable table(materials());
  ViscoelasticCondensationParameters parameters = bench_parameters();
  ViscoelasticCondensation sole(tria, disc, table, parameters);
  const unsigned int n = 3 * sole.n_contacts();
  dealii::Vector<double> f(n), u(n);
  const std::vector<double>& C = sole.effective_compliance();
  const int steps = 200;
  double field = 0, history = 0, product = 0;
  for (int step = 1; step <= steps; ++step) {
    load_at(step * 1e-3, sole.n_contacts(), f);
    const auto start = std::chrono::steady_clock::now();
    for (unsigned int i = 0; i < n; ++i) {
      double sum = sole.history_displacement()(i);
      for (unsigned int j = 0; j < n; ++j)
        sum += C[std::size_t{i} * n + j] * f(j);
      u(i) = sum;
    }
    product += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sole.advance(f);
    field += sole.timings().field_solve;
    history += sole.timings().history;
  }
  const auto& s = sole.timings();
  std::printf("| %s %ux%ux%u | %u | %u | %zu | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n",
              disc.name().c_str(), cells[0], cells[1], cells[2], sole.n_dofs(), sole.n_contacts(),
              sole.n_internal_variables(), s.assembly, s.factorization, s.condensation,
              1e3 * field / steps, 1e3 * history / steps, 1e3 * product / steps);
}

// The separable sole in both forms.
void run_separable(CellKind kind, unsigned int degree, unsigned int refinement) {
  dealii::Triangulation<3> tria;
  make_box(kind, refinement, tria);
  const Discretization disc(kind, degree);
  const ViscoelasticMaterialTable table(separable_materials());
  ViscoelasticCondensationParameters parameters = bench_parameters();
  ViscoelasticCondensation quadrature(tria, disc, table, parameters);
  parameters.cell_dissipation = false;
  ViscoelasticCondensation contact(tria, disc, table, parameters);
  const unsigned int n = 3 * contact.n_contacts();
  dealii::Vector<double> f(n), difference(n);
  const int steps = 200;
  double quadrature_time = 0, contact_time = 0, worst = 0, largest = 0;
  for (int step = 1; step <= steps; ++step) {
    load_at(step * 1e-3, contact.n_contacts(), f);
    quadrature.advance(f);
    quadrature_time += quadrature.timings().field_solve + quadrature.timings().history;
    contact.advance(f);
    contact_time += contact.timings().history;
    difference = contact.contact_displacement();
    difference -= quadrature.contact_displacement();
    worst = std::max(worst, difference.linfty_norm());
    largest = std::max(largest, quadrature.contact_displacement().linfty_norm());
  }
  std::printf("| %s r%u | %u | %u | %.3f | %.4f | %.0f | %.1e |\n", disc.name().c_str(), refinement,
              contact.n_dofs(), contact.n_contacts(), 1e3 * quadrature_time / steps,
              1e3 * contact_time / steps, quadrature_time / contact_time, worst / largest);
}

} // namespace

int main() {
  std::printf("| mesh | dofs | contact nodes | h_i tensors | assembly s | LU s | condensation s "
              "| field solve ms/step | history ms/step | C_eff f ms/step |\n"
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const unsigned int refinement : {1u, 2u, 3u, 4u})
    run(CellKind::hexahedron, 1, refinement);
  for (const unsigned int refinement : {1u, 2u})
    run(CellKind::hexahedron, 2, refinement);
  for (const unsigned int refinement : {1u, 2u, 3u})
    run(CellKind::tetrahedron, 1, refinement);
  for (const unsigned int refinement : {1u, 2u})
    run(CellKind::tetrahedron, 2, refinement);
  std::printf("\n| separable sole | dofs | contact nodes | quadrature form ms/step | contact space "
              "ms/step | ratio | max |u_c difference| / max |u_c| |\n"
              "| --- | --- | --- | --- | --- | --- | --- |\n");
  for (const unsigned int refinement : {1u, 2u, 4u})
    run_separable(CellKind::hexahedron, 1, refinement);
  for (const unsigned int refinement : {1u, 2u})
    run_separable(CellKind::hexahedron, 2, refinement);
  for (const unsigned int refinement : {1u, 3u})
    run_separable(CellKind::tetrahedron, 1, refinement);
  return 0;
}
