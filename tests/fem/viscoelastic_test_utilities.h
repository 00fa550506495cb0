#pragma once
// Helpers of the viscoelastic tests: a bar (nu = 0 in every branch, so that a bar clamped at
// x = 0 and pulled at x = L is in uniaxial stress and Q1 elements are exact) driven through the
// condensed sole by forces or by prescribed end displacements, and Prony closed forms.

#include "fem/viscoelastic_condensation.h"
#include "fem_test_utilities.h"

#include <deal.II/lac/full_matrix.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace plantar::fem::testing {

/// A uniaxial Prony series: E(t) = E_inf + sum_i E_i exp(-t/tau_i).
struct UniaxialProny {
  double long_term = 1e6;                       ///< E_inf, Pa
  std::vector<std::pair<double, double>> terms; ///< (E_i Pa, tau_i s)

  /// The 3D law with nu = 0 in every branch: G = E/2, K = E/3.
  ViscoelasticMaterial material() const {
    std::vector<PronyBranch> branches;
    for (const auto& [modulus, tau] : terms)
      branches.push_back({modulus / 2.0, modulus / 3.0, tau});
    return ViscoelasticMaterial(long_term / 2.0, long_term / 3.0, branches, "bar");
  }
  double relaxation(double t) const {
    double e = long_term;
    for (const auto& [modulus, tau] : terms)
      e += modulus * std::exp(-t / tau);
    return e;
  }
  double instantaneous() const { return relaxation(0.0); }
  double tau_min() const {
    double t = terms.front().second;
    for (const auto& term : terms)
      t = std::min(t, term.second);
    return t;
  }
  double tau_max() const {
    double t = terms.front().second;
    for (const auto& term : terms)
      t = std::max(t, term.second);
    return t;
  }
};

/// Creep compliance J(t) of a Prony series, from its Laplace transform: with
/// g(s) = E_inf + sum_i E_i s / (s + 1/tau_i), J^(s) = 1 / (s g(s)), so
///   J(t) = 1/E_inf + sum_k exp(s_k t) / (s_k g'(s_k)),
/// s_k the N roots of g, one in each interval between the poles -1/tau_i (found by bisection).
class CreepCompliance {
public:
  explicit CreepCompliance(const UniaxialProny& prony) : prony_(prony) {
    std::vector<double> rates;
    for (const auto& term : prony.terms)
      rates.push_back(1.0 / term.second);
    std::sort(rates.begin(), rates.end());
    double upper = 0.0; // g(upper-) > 0, g -> -inf at the next pole from above
    for (const double rate : rates) {
      double hi = upper, lo = -rate;
      for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (g(mid) > 0 ? hi : lo) = mid;
      }
      const double root = 0.5 * (lo + hi);
      roots_.push_back(root);
      slopes_.push_back(g_prime(root));
      upper = -rate;
    }
  }
  /// J(t), 1/Pa: strain under a unit stress step at t = 0.
  double operator()(double t) const {
    double j = 1.0 / prony_.long_term;
    for (std::size_t k = 0; k < roots_.size(); ++k)
      j += std::exp(roots_[k] * t) / (roots_[k] * slopes_[k]);
    return j;
  }
  /// int_0^t J(s) ds, s/Pa.
  double integral(double t) const {
    double i = t / prony_.long_term;
    for (std::size_t k = 0; k < roots_.size(); ++k)
      i += std::expm1(roots_[k] * t) / (roots_[k] * roots_[k] * slopes_[k]);
    return i;
  }
  /// Strain at t >= ramp under a unit stress ramped linearly over [0, ramp], then held:
  /// (1/ramp) int_0^ramp J(t - s) ds.
  double ramp(double t, double ramp_time) const {
    return (integral(t) - integral(t - ramp_time)) / ramp_time;
  }

private:
  double g(double s) const {
    double v = prony_.long_term;
    for (const auto& [modulus, tau] : prony_.terms)
      v += modulus * s / (s + 1.0 / tau);
    return v;
  }
  double g_prime(double s) const {
    double v = 0;
    for (const auto& [modulus, tau] : prony_.terms)
      v += modulus * (1.0 / tau) / ((s + 1.0 / tau) * (s + 1.0 / tau));
    return v;
  }
  UniaxialProny prony_;
  std::vector<double> roots_, slopes_;
};

/// Bar [0, L] x [0, b] x [0, b], n Q1 cells along x, clamped at x = 0 (id 0), contact nodes
/// at x = L (id 1).
struct Bar {
  static constexpr double length = 0.1, side = 0.02;
  dealii::Triangulation<3> tria;
  Discretization disc{CellKind::hexahedron, 1};
  ViscoelasticMaterialTable materials;
  std::unique_ptr<ViscoelasticCondensation> sole;
  dealii::FullMatrix<double> stiffness; // C_eff^-1
  dealii::Vector<double> forces, target, gap;

  Bar(const UniaxialProny& prony, double dt, unsigned int cells = 4) : materials(prony.material()) {
    make_box(tria, CellKind::hexahedron, cells, 1, 1, length, side, side);
    ViscoelasticCondensationParameters parameters;
    parameters.attached_boundary = 0;
    parameters.contact_boundary = 1;
    parameters.time_step = dt;
    sole = std::make_unique<ViscoelasticCondensation>(tria, disc, materials, parameters);
    const unsigned int n = 3 * sole->n_contacts();
    stiffness.reinit(n, n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        stiffness(i, j) = sole->effective_compliance()[i * n + j];
    stiffness.gauss_jordan();
    forces.reinit(n);
    target.reinit(n);
    gap.reinit(n);
  }
  double area() const { return side * side; }
  /// One step with the total axial force @p force (N) shared equally by the end nodes (the
  /// consistent nodal forces of a uniform traction on one Q1 face); returns the axial strain.
  double step_force(double force) {
    forces = 0;
    for (unsigned int k = 0; k < sole->n_contacts(); ++k)
      forces(3 * k) = force / sole->n_contacts();
    sole->advance(forces);
    return sole->contact_displacement()(0) / length;
  }
  /// One step with the end face at u = (strain L, 0, 0): f = C_eff^-1 (u - d); returns the
  /// axial stress (Pa), the sum of the end forces over the area.
  double step_strain(double strain) {
    for (unsigned int k = 0; k < sole->n_contacts(); ++k)
      target(3 * k) = strain * length;
    gap = target;
    gap -= sole->history_displacement();
    stiffness.vmult(forces, gap);
    sole->advance(forces);
    double total = 0;
    for (unsigned int k = 0; k < sole->n_contacts(); ++k)
      total += forces(3 * k);
    return total / area();
  }
};

} // namespace plantar::fem::testing
