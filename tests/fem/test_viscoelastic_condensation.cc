// The condensed viscoelastic sole (fem/viscoelastic_condensation.h):
//  - condensed vs full: u_c = C_eff f + d equals a direct full-field time integration written
//    here with global matrices (q_ri = int_{region r} B^T h_i, updated as
//    q^{n+1} = e q^n + gamma K_ri (u^{n+1} - u^n), solved with deal.II's UMFPACK), on a
//    two-material sole whose regions relax differently (non-proportional damping);
//  - limits: dt -> 0 and dt -> inf, and a held load, against linear elastic solves
//    (fem::LinearElasticity) with G_0, K_0 and G_inf, K_inf;
//  - the contact-space form of a separable sole (branches proportional per region) against the
//    quadrature form: displacements, history, energies, fields to round-off; non-separable
//    soles keep the quadrature form;
//  - no heap allocation in advance() (both forms); bad input.
#include "fem/linear_elasticity.h"
#include "fem/material_table.h"
#include "fem/viscoelastic_condensation.h"
#include "fem_test_utilities.h"

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "tests/allocation_counter.h"

namespace plantar::fem {
namespace {

using dealii::types::material_id;

constexpr double a = 0.06, b = 0.04, c = 0.02; // box, m; attached z = c (id 5), contact z = 0 (4)

// Region 0 (heel, y < b/2): E, nu with two proportional branches. Region 1: G, K with a
// shear-only branch and a branch relaxing shear and bulk: regions relax differently.
std::map<material_id, ViscoelasticMaterial> two_materials() {
  const double nu = 0.45, E = 2e6;
  auto g = [nu](double e) { return e / (2 * (1 + nu)); };
  auto k = [nu](double e) { return e / (3 * (1 - 2 * nu)); };
  std::map<material_id, ViscoelasticMaterial> m;
  m.emplace(0, ViscoelasticMaterial(g(E), k(E), {{g(3e6), k(3e6), 1e-3}, {g(1e6), k(1e6), 5e-2}},
                                    "heel"));
  m.emplace(1, ViscoelasticMaterial(0.5e6, 5e6, {{1e6, 0.0, 2e-2}, {0.3e6, 1e6, 0.3}}, "fore"));
  return m;
}

void make_sole(dealii::Triangulation<3>& tria, CellKind kind, unsigned int nx, unsigned int ny,
               unsigned int nz) {
  testing::make_box(tria, kind, nx, ny, nz, a, b, c);
  for (const auto& cell : tria.active_cell_iterators())
    cell->set_material_id(cell->center()[1] < b / 2 ? 0 : 1);
}

ViscoelasticCondensationParameters parameters(double dt) {
  ViscoelasticCondensationParameters p;
  p.attached_boundary = 5;
  p.contact_boundary = 4;
  p.time_step = dt;
  p.block_size = 7; // several blocks, one partial
  return p;
}

// Contact forces at t (N): a pressing load and a sliding traction, different per node.
void forces_at(double t, unsigned int n_contacts, dealii::Vector<double>& f) {
  for (unsigned int k = 0; k < n_contacts; ++k) {
    f(3 * k + 0) = 2.0 * std::sin(2 * M_PI * 3 * t + k);
    f(3 * k + 1) = 1.0 * std::cos(2 * M_PI * 11 * t + 0.5 * k) * (t < 0.1 ? 1 : 0);
    f(3 * k + 2) = -5.0 * (1 - std::cos(2 * M_PI * 7 * t)) * (1 + 0.1 * (k % 5));
  }
}

// The direct full-field integration with global matrices (see above).
class DirectIntegration {
public:
  DirectIntegration(const ViscoelasticCondensation& sole, const Discretization& disc,
                    const std::map<material_id, ViscoelasticMaterial>& materials, double dt)
      : sole_(sole) {
    const auto& dofs = sole.dof_handler();
    dealii::DynamicSparsityPattern dsp(dofs.n_dofs());
    dealii::DoFTools::make_sparsity_pattern(dofs, dsp, sole.constraints(), false);
    sparsity_.copy_from(dsp);
    long_term_.reinit(sparsity_);
    for (const auto& [id, material] : materials)
      for (unsigned int i = 0; i < material.n_branches(); ++i) {
        Term term;
        term.region = id;
        term.stiffness = std::make_unique<dealii::SparseMatrix<double>>(sparsity_);
        const double tau = material.branches()[i].relaxation_time;
        term.decay = std::exp(-dt / tau);
        term.gamma = tau / dt * (1 - std::exp(-dt / tau));
        term.q.reinit(dofs.n_dofs());
        assemble(disc, id, material.branch_stiffness(i), *term.stiffness);
        terms_.push_back(std::move(term));
      }
    for (const auto& [id, material] : materials)
      assemble(disc, id, material.long_term_stiffness(), long_term_);
    effective_.reinit(sparsity_);
    effective_.copy_from(long_term_);
    for (const Term& term : terms_)
      effective_.add(term.gamma, *term.stiffness);
    lu_.initialize(effective_);
    u_.reinit(dofs.n_dofs());
    rhs_.reinit(dofs.n_dofs());
    work_.reinit(dofs.n_dofs());
  }

  /// One step under the contact forces @p f; returns u^{n+1} on the contact dofs.
  void step(const dealii::Vector<double>& f, dealii::Vector<double>& contact) {
    rhs_ = 0;
    const auto& nodes = sole_.contact_dofs();
    for (unsigned int k = 0; k < nodes.size(); ++k)
      for (unsigned int d = 0; d < 3; ++d)
        rhs_(nodes[k][d]) = f(3 * k + d);
    for (const Term& term : terms_) { // - (e q - gamma K u^n)
      rhs_.add(-term.decay, term.q);
      term.stiffness->vmult(work_, u_);
      rhs_.add(term.gamma, work_);
    }
    dealii::Vector<double> next(rhs_);
    lu_.solve(next);
    work_ = next;
    work_ -= u_;
    dealii::Vector<double> increment(work_);
    for (Term& term : terms_) {
      term.stiffness->vmult(work_, increment);
      term.q *= term.decay;
      term.q.add(term.gamma, work_);
    }
    u_ = next;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      for (unsigned int d = 0; d < 3; ++d)
        contact(3 * k + d) = u_(nodes[k][d]);
  }

private:
  struct Term {
    material_id region = 0;
    std::unique_ptr<dealii::SparseMatrix<double>> stiffness; // K_ri
    double decay = 0, gamma = 0;
    dealii::Vector<double> q; // int B^T h_ri
  };

  void assemble(const Discretization& disc, material_id region,
                const dealii::SymmetricTensor<4, 3>& C, dealii::SparseMatrix<double>& matrix) {
    dealii::FEValues<3> fe_values(*disc.mapping, *disc.fe, disc.cell_quadrature,
                                  dealii::update_gradients | dealii::update_JxW_values);
    const unsigned int n = disc.fe->n_dofs_per_cell();
    dealii::FullMatrix<double> cell_matrix(n, n);
    std::vector<dealii::types::global_dof_index> dofs(n);
    const dealii::FEValuesExtractors::Vector u(0);
    for (const auto& cell : sole_.dof_handler().active_cell_iterators()) {
      if (cell->material_id() != region)
        continue;
      fe_values.reinit(cell);
      cell_matrix = 0;
      for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j < n; ++j)
            cell_matrix(i, j) += fe_values[u].symmetric_gradient(i, q) * C *
                                 fe_values[u].symmetric_gradient(j, q) * fe_values.JxW(q);
      cell->get_dof_indices(dofs);
      sole_.constraints().distribute_local_to_global(cell_matrix, dofs, matrix);
    }
  }

  const ViscoelasticCondensation& sole_;
  dealii::SparsityPattern sparsity_;
  dealii::SparseMatrix<double> long_term_, effective_;
  std::vector<Term> terms_;
  dealii::SparseDirectUMFPACK lu_;
  dealii::Vector<double> u_, rhs_, work_;
};

struct Case {
  CellKind kind;
  unsigned int degree, nx, ny, nz;
};

TEST(ViscoelasticCondensation, CondensedEqualsTheFullTimeIntegrationOnATwoMaterialSole) {
  for (const Case& test :
       {Case{CellKind::hexahedron, 1, 4, 4, 2}, Case{CellKind::tetrahedron, 2, 2, 2, 1}}) {
    dealii::Triangulation<3> tria;
    make_sole(tria, test.kind, test.nx, test.ny, test.nz);
    const Discretization disc(test.kind, test.degree);
    const auto by_id = two_materials();
    const ViscoelasticMaterialTable table(by_id);
    const double dt = 2e-3;
    ViscoelasticCondensation sole(tria, disc, table, parameters(dt));
    DirectIntegration direct(sole, disc, by_id, dt);
    EXPECT_LT(sole.raw_asymmetry(), 1e-12);

    const unsigned int n = 3 * sole.n_contacts();
    const std::vector<double>& C = sole.effective_compliance();
    dealii::Vector<double> f(n), condensed(n), reference(n);
    double worst = 0, largest = 0, largest_history = 0, consistency = 0;
    for (int step = 1; step <= 300; ++step) {
      forces_at(step * dt, sole.n_contacts(), f);
      for (unsigned int i = 0; i < n; ++i) { // u_c = C_eff f + d
        condensed(i) = sole.history_displacement()(i);
        for (unsigned int j = 0; j < n; ++j)
          condensed(i) += C[std::size_t{i} * n + j] * f(j);
      }
      largest_history = std::max(largest_history, sole.history_displacement().linfty_norm());
      sole.advance(f);
      direct.step(f, reference);
      for (unsigned int i = 0; i < n; ++i) {
        worst = std::max(worst, std::abs(condensed(i) - reference(i)));
        consistency =
            std::max(consistency, std::abs(condensed(i) - sole.contact_displacement()(i)));
      }
      largest = std::max(largest, reference.linfty_norm());
    }
    SCOPED_TRACE(disc.name());
    std::printf("%s: %u dofs, %u contact nodes, %zu internal variables; condensed vs full "
                "%.2e relative, max |d| / max |u| = %.2f\n",
                disc.name().c_str(), sole.n_dofs(), sole.n_contacts(), sole.n_internal_variables(),
                worst / largest, largest_history / largest);
    EXPECT_LT(worst, 1e-8 * largest);
    EXPECT_LT(consistency, 1e-10 * largest);
    EXPECT_GT(largest_history, 0.1 * largest); // the history term matters here
  }
}

// Contact displacements of a linear elastic solve (fem::LinearElasticity) of the same sole with
// per-region moduli G, K under the contact forces f.
dealii::Vector<double> elastic_response(const dealii::Triangulation<3>& tria,
                                        const Discretization& disc,
                                        const std::map<material_id, std::pair<double, double>>& gk,
                                        const ViscoelasticCondensation& sole,
                                        const dealii::Vector<double>& f) {
  std::map<std::string, MaterialSpec> specs;
  PhysicalGroups groups;
  groups.file = "generated box";
  for (const auto& [id, moduli] : gk) {
    const auto [G, K] = moduli;
    const std::string name = "region" + std::to_string(id);
    specs[name] =
        MaterialSpec{name,
                     "linear",
                     {{"E", 9 * K * G / (3 * K + G)}, {"nu", (3 * K - 2 * G) / (2 * (3 * K + G))}}};
    groups.volumes[name] = id;
  }
  for (const auto& cell : tria.active_cell_iterators())
    ++groups.n_cells[cell->material_id()];
  const MaterialTable materials(specs, groups);
  LinearElasticity problem(tria, disc, materials);
  problem.setup({{5, nullptr}});
  problem.assemble();
  const auto nodes = problem.boundary_nodes(4);
  EXPECT_EQ(nodes, sole.contact_dofs());
  for (unsigned int k = 0; k < nodes.size(); ++k)
    for (unsigned int d = 0; d < 3; ++d)
      problem.load()(nodes[k][d]) += f(3 * k + d);
  problem.solve();
  dealii::Vector<double> u(f.size());
  for (unsigned int k = 0; k < nodes.size(); ++k)
    for (unsigned int d = 0; d < 3; ++d)
      u(3 * k + d) = problem.solution()(nodes[k][d]);
  return u;
}

std::map<material_id, std::pair<double, double>> moduli(bool instantaneous) {
  std::map<material_id, std::pair<double, double>> gk;
  for (const auto& [id, m] : two_materials())
    gk[id] = instantaneous ? std::pair{m.shear_relaxation(0), m.bulk_relaxation(0)}
                           : std::pair{m.shear_modulus(), m.bulk_modulus()};
  return gk;
}

double relative_difference(const dealii::Vector<double>& x, const dealii::Vector<double>& y) {
  dealii::Vector<double> d(x);
  d -= y;
  return d.linfty_norm() / y.linfty_norm();
}

TEST(ViscoelasticCondensation, InstantaneousAndLongTermLimitsAreElasticSolves) {
  dealii::Triangulation<3> tria;
  make_sole(tria, CellKind::hexahedron, 4, 4, 2);
  const Discretization disc(CellKind::hexahedron, 1);
  const ViscoelasticMaterialTable table(two_materials());
  const double tau_min = 1e-3, tau_max = 0.3;
  for (const bool instantaneous : {true, false}) {
    // dt / tau_min = 1e-8 (gamma_i = 1 - O(1e-8)) or dt / tau_max = 1e8 (gamma_i = O(1e-8)).
    const double dt = instantaneous ? 1e-8 * tau_min : 1e8 * tau_max;
    ViscoelasticCondensation sole(tria, disc, table, parameters(dt));
    dealii::Vector<double> f(3 * sole.n_contacts()), u(3 * sole.n_contacts());
    forces_at(0.013, sole.n_contacts(), f);
    sole.advance(f); // from rest: u_c = C_eff f
    const auto elastic = elastic_response(tria, disc, moduli(instantaneous), sole, f);
    SCOPED_TRACE(instantaneous ? "instantaneous" : "long term");
    EXPECT_LT(relative_difference(sole.contact_displacement(), elastic), 1e-6);
  }
  // A held load at dt = tau_max / 2: after 200 steps (e^{-400} of every branch left) the
  // long-term elastic answer.
  ViscoelasticCondensation sole(tria, disc, table, parameters(tau_max / 2));
  dealii::Vector<double> f(3 * sole.n_contacts());
  forces_at(0.013, sole.n_contacts(), f);
  const auto first_elastic = elastic_response(tria, disc, moduli(true), sole, f);
  for (int step = 0; step < 200; ++step)
    sole.advance(f);
  EXPECT_LT(relative_difference(sole.contact_displacement(),
                                elastic_response(tria, disc, moduli(false), sole, f)),
            1e-10);
  EXPECT_GT(relative_difference(sole.contact_displacement(), first_elastic), 0.1);
}

// Two regions of different moduli and Poisson ratios sharing one relaxation spectrum shape
// (E_i / E = 1.5 and 0.5 at tau 1 ms and 50 ms, law=prony with E<i>): separable.
std::map<material_id, ViscoelasticMaterial> separable_materials() {
  auto prony = [](double E, double nu, const std::string& name) {
    auto g = [nu](double e) { return e / (2 * (1 + nu)); };
    auto k = [nu](double e) { return e / (3 * (1 - 2 * nu)); };
    return ViscoelasticMaterial(
        g(E), k(E), {{g(1.5 * E), k(1.5 * E), 1e-3}, {g(0.5 * E), k(0.5 * E), 5e-2}}, name);
  };
  std::map<material_id, ViscoelasticMaterial> m;
  m.emplace(0, prony(2e6, 0.45, "heel"));
  m.emplace(1, prony(5e6, 0.3, "fore"));
  return m;
}

TEST(ViscoelasticCondensation, ContactSpaceFormEqualsTheQuadratureForm) {
  for (const Case& test :
       {Case{CellKind::hexahedron, 1, 4, 4, 2}, Case{CellKind::tetrahedron, 2, 2, 2, 1}}) {
    dealii::Triangulation<3> tria;
    make_sole(tria, test.kind, test.nx, test.ny, test.nz);
    const Discretization disc(test.kind, test.degree);
    SCOPED_TRACE(disc.name());
    const ViscoelasticMaterialTable table(separable_materials());
    const double dt = 2e-3;
    ViscoelasticCondensation quadrature(tria, disc, table, parameters(dt));
    ViscoelasticCondensationParameters p = parameters(dt);
    p.cell_dissipation = false;
    ViscoelasticCondensation contact(tria, disc, table, p);
    // The same, advanced with the caller's u_c = C_eff f + d^n (as a contact solve has it).
    ViscoelasticCondensation given(tria, disc, table, p);
    EXPECT_TRUE(quadrature.separable() && contact.separable());
    EXPECT_FALSE(quadrature.contact_space());
    ASSERT_TRUE(contact.contact_space());
    EXPECT_EQ(contact.n_internal_variables(), 0u);
    EXPECT_TRUE(contact.cell_dissipated_energy().empty());

    const unsigned int n = 3 * contact.n_contacts();
    dealii::Vector<double> f(n), u(n);
    double worst_u = 0, worst_d = 0, worst_given = 0;
    for (int step = 1; step <= 300; ++step) {
      forces_at(step * dt, contact.n_contacts(), f);
      for (unsigned int r = 0; r < n; ++r) {
        u(r) = given.history_displacement()(r);
        for (unsigned int j = 0; j < n; ++j)
          u(r) += given.effective_compliance()[std::size_t{r} * n + j] * f(j);
      }
      quadrature.advance(f, &u); // ignored by the quadrature form (compared with contact below)
      contact.advance(f);
      given.advance(f, &u);
      worst_given = std::max(worst_given, relative_difference(given.contact_displacement(),
                                                              contact.contact_displacement()));
      worst_given = std::max(worst_given, relative_difference(given.history_displacement(),
                                                              contact.history_displacement()));
      worst_u = std::max(worst_u, relative_difference(contact.contact_displacement(),
                                                      quadrature.contact_displacement()));
      if (quadrature.history_displacement().linfty_norm() > 0)
        worst_d = std::max(worst_d, relative_difference(contact.history_displacement(),
                                                        quadrature.history_displacement()));
      if (step % 100 == 0) { // energies and fields at a few steps
        const double work = quadrature.external_work(), stored = quadrature.stored_energy();
        const double dissipated = quadrature.dissipated_energy();
        EXPECT_NEAR(contact.external_work(), work, 1e-10 * std::abs(work));
        EXPECT_NEAR(contact.stored_energy(), stored, 1e-10 * stored);
        EXPECT_NEAR(contact.dissipated_energy(), dissipated, 1e-10 * dissipated);
        EXPECT_GT(dissipated, 1e-3 * std::abs(work)); // the branches dissipate here
        EXPECT_LT(relative_difference(contact.solution(), quadrature.solution()), 1e-10);
        const ViscoelasticCellFields a = contact.cell_fields(), b = quadrature.cell_fields();
        EXPECT_TRUE(a.dissipated_energy_density.empty());
        ASSERT_EQ(a.overstress.size(), 2u);
        auto worst = [](const std::vector<double>& x, const std::vector<double>& y) {
          double d = 0, m = 0;
          for (std::size_t i = 0; i < x.size(); ++i) {
            d = std::max(d, std::abs(x[i] - y[i]));
            m = std::max(m, std::abs(y[i]));
          }
          return d / m;
        };
        EXPECT_LT(worst(a.von_mises, b.von_mises), 1e-10);
        EXPECT_LT(worst(a.overstress[0], b.overstress[0]), 1e-10);
        EXPECT_LT(worst(a.overstress[1], b.overstress[1]), 1e-10);
        EXPECT_LT((contact.mean_strain() - quadrature.mean_strain()).norm(),
                  1e-10 * quadrature.mean_strain().norm());
      }
    }
    std::printf("%s: contact space vs quadrature points: u_c %.1e, d %.1e (relative, max over "
                "300 steps); with the caller's u_c: %.1e\n",
                disc.name().c_str(), worst_u, worst_d, worst_given);
    EXPECT_NEAR(given.dissipated_energy(), contact.dissipated_energy(),
                1e-12 * contact.dissipated_energy());
    EXPECT_NEAR(given.external_work(), contact.external_work(),
                1e-12 * std::abs(contact.external_work()));
    EXPECT_LT(worst_given, 1e-12);
    EXPECT_LT(worst_u, 1e-10);
    EXPECT_LT(worst_d, 1e-10);
    // Back to rest: the same response again.
    contact.reset();
    quadrature.reset();
    forces_at(dt, contact.n_contacts(), f);
    contact.advance(f);
    quadrature.advance(f);
    EXPECT_LT(
        relative_difference(contact.contact_displacement(), quadrature.contact_displacement()),
        1e-12);
  }
}

TEST(ViscoelasticCondensation, NonSeparableSolesKeepTheQuadratureForm) {
  dealii::Triangulation<3> tria;
  make_sole(tria, CellKind::hexahedron, 2, 2, 1);
  const Discretization disc(CellKind::hexahedron, 1);
  ViscoelasticCondensationParameters p = parameters(1e-3);
  p.cell_dissipation = false;
  // Regions relaxing differently (a shear-only branch in one).
  const ViscoelasticMaterialTable different(two_materials());
  ViscoelasticCondensation first(tria, disc, different, p);
  EXPECT_FALSE(first.separable());
  EXPECT_FALSE(first.contact_space());
  EXPECT_GT(first.n_internal_variables(), 0u);
  // A proportional region next to an elastic one.
  auto with_elastic_by_id = separable_materials();
  with_elastic_by_id.erase(1);
  with_elastic_by_id.emplace(1, ViscoelasticMaterial(1e6, 3e6, {}, "plate"));
  const ViscoelasticMaterialTable with_elastic(with_elastic_by_id);
  ViscoelasticCondensation second(tria, disc, with_elastic, p);
  EXPECT_FALSE(second.separable());
  // The same spectrum shape at another relaxation time in one region.
  auto other_time_by_id = separable_materials();
  const ViscoelasticMaterial fore = other_time_by_id.at(1); // a copy: erased below
  std::vector<PronyBranch> branches = fore.branches();
  branches[1].relaxation_time = 6e-2;
  other_time_by_id.erase(1);
  other_time_by_id.emplace(
      1, ViscoelasticMaterial(fore.shear_modulus(), fore.bulk_modulus(), branches));
  const ViscoelasticMaterialTable other_time(other_time_by_id);
  ViscoelasticCondensation third(tria, disc, other_time, p);
  EXPECT_FALSE(third.separable());
}

TEST(ViscoelasticCondensation, AdvanceDoesNotAllocate) {
  for (const bool contact_space : {false, true}) {
    dealii::Triangulation<3> tria;
    make_sole(tria, CellKind::hexahedron, 3, 3, 2);
    const Discretization disc(CellKind::hexahedron, 1);
    const ViscoelasticMaterialTable table(contact_space ? separable_materials() : two_materials());
    ViscoelasticCondensationParameters p = parameters(1e-3);
    p.cell_dissipation = !contact_space;
    ViscoelasticCondensation sole(tria, disc, table, p);
    EXPECT_EQ(sole.contact_space(), contact_space);
    dealii::Vector<double> f(3 * sole.n_contacts());
    forces_at(0.01, sole.n_contacts(), f);
    sole.advance(f);
    plantar::testing::n_allocations = 0;
    plantar::testing::counting = true;
    void* live = ::operator new(sizeof(int)); // the counter is live (an explicit call)
    ::operator delete(live);
    const long baseline = plantar::testing::n_allocations;
    for (int step = 0; step < 5; ++step)
      sole.advance(f);
    plantar::testing::counting = false;
    EXPECT_EQ(baseline, 1);
    EXPECT_EQ(plantar::testing::n_allocations - baseline, 0);
  }
}

TEST(ViscoelasticBadInput, ParametersAreNamedWithValueAndRange) {
  auto message = [](auto&& build) {
    try {
      build();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  auto contains = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  std::string m = message([] { ViscoelasticMaterial(-1.0, 1e6, {}, "rubber"); });
  EXPECT_TRUE(contains(m, "G_inf = -1") && contains(m, "rubber") && contains(m, "[0, inf)")) << m;
  m = message([] { ViscoelasticMaterial(1e6, 1e6, {{1e6, 0, 1e-3}, {1e6, 0, -2}}, "rubber"); });
  EXPECT_TRUE(contains(m, "tau2 = -2") && contains(m, "(0, inf)")) << m;
  m = message([] { ViscoelasticMaterial(1e6, 1e6, {{-3, 0, 1e-3}}, "rubber"); });
  EXPECT_TRUE(contains(m, "G1 = -3")) << m;
  m = message([] { ViscoelasticMaterial(1e6, 1e6, {{1, -4, 1e-3}}, "rubber"); });
  EXPECT_TRUE(contains(m, "K1 = -4")) << m;
  m = message([] { ViscoelasticMaterial(0.0, 1e6, {}, "rubber"); });
  EXPECT_TRUE(contains(m, "G_0")) << m;
  auto spec = [](const std::string& text) {
    return ViscoelasticMaterial::from_spec(parse_material_specs(text, "Materials").begin()->second);
  };
  m = message([&] { spec("r: law=prony, E=2e6, nu=0.45, E1=3e6, tau1=0"); });
  EXPECT_TRUE(contains(m, "tau1 = 0")) << m;
  m = message([&] { spec("r: law=prony, E=2e6, nu=0.45, E1=-3e6, tau1=1"); });
  EXPECT_TRUE(contains(m, "E1 = -3e+06")) << m;
  m = message([&] { spec("r: law=prony, E=2e6, nu=0.5, E1=3e6, tau1=1"); });
  EXPECT_TRUE(contains(m, "nu = 0.5") && contains(m, "(-1, 0.5)")) << m;
  m = message([&] { spec("r: law=prony, E=2e6, nu=0.45, E1=3e6"); });
  EXPECT_TRUE(contains(m, "tau1")) << m;
  m = message([&] { spec("r: law=prony, E=2e6, nu=0.45, E2=3e6, tau2=1"); });
  EXPECT_TRUE(contains(m, "branch 1 is missing")) << m;
  m = message([&] { spec("r: law=prony, E=2e6, nu=0.45, eta1=3e6, tau1=1"); });
  EXPECT_TRUE(contains(m, "unknown parameter 'eta1'")) << m;
  m = message([&] { spec("r: law=maxwell, E=2e6"); });
  EXPECT_TRUE(contains(m, "law 'maxwell'")) << m;
  m = message([] {
    ViscoelasticCondensationParameters p;
    p.time_step = -1e-3;
    p.validate();
  });
  EXPECT_TRUE(contains(m, "time_step = -0.001")) << m;
}

TEST(ViscoelasticMaterialSpec, SceneSyntaxGivesTheRelaxationFunctions) {
  const auto specs = parse_material_specs(
      "heel: law=prony, E=2e6, nu=0.45, E1=3e6, tau1=1e-3, E2=1e6, tau2=0.05; "
      "fore: law=prony, G=5e5, K=5e6, G1=1e6, tau1=0.02, G2=3e5, K2=1e6, tau2=0.3; "
      "plate: E=4e6, nu=0.3",
      "Materials");
  const auto heel = ViscoelasticMaterial::from_spec(specs.at("heel"));
  const auto fore = ViscoelasticMaterial::from_spec(specs.at("fore"));
  const auto plate = ViscoelasticMaterial::from_spec(specs.at("plate"));
  // E(t) = 9 K G / (3 K + G) with proportional branches: E_inf + sum E_i e^{-t/tau_i}.
  for (const double t : {0.0, 1e-3, 0.05, 1.0}) {
    const double G = heel.shear_relaxation(t), K = heel.bulk_relaxation(t);
    const double E = 2e6 + 3e6 * std::exp(-t / 1e-3) + 1e6 * std::exp(-t / 0.05);
    EXPECT_NEAR(9 * K * G / (3 * K + G), E, 1e-9 * E);
  }
  EXPECT_DOUBLE_EQ(fore.shear_relaxation(0.1),
                   5e5 + 1e6 * std::exp(-0.1 / 0.02) + 3e5 * std::exp(-0.1 / 0.3));
  EXPECT_DOUBLE_EQ(fore.bulk_relaxation(0.1), 5e6 + 1e6 * std::exp(-0.1 / 0.3));
  EXPECT_EQ(plate.n_branches(), 0u);
  EXPECT_NEAR(plate.shear_modulus(), 4e6 / 2.6, 1e-6);
  // gamma: the limits 1 (dt << tau) and tau/dt (dt >> tau), and the exact value.
  double e = 0, g = 0;
  ViscoelasticMaterial::step_factors(1e-12, 1.0, e, g);
  EXPECT_NEAR(g, 1.0 - 0.5e-12, 1e-16);
  ViscoelasticMaterial::step_factors(1e3, 1.0, e, g);
  EXPECT_DOUBLE_EQ(g, 1e-3);
  ViscoelasticMaterial::step_factors(0.7, 0.3, e, g);
  EXPECT_NEAR(g, 0.3 / 0.7 * (1 - std::exp(-0.7 / 0.3)), 1e-15);
  EXPECT_NEAR(e, std::exp(-0.7 / 0.3), 1e-15);
}

} // namespace
} // namespace plantar::fem
