// Manufactured solution on the unit cube: L2 and H1 error rates for P1, P2,
// Q1, Q2 (validation.md, "Manufactured solution").
//   u = c phi, phi = sin(pi x) sin(pi y) sin(pi z), c = (1, 2, 3) * 1e-3 m
//   f = -div sigma = 3 pi^2 mu c phi - (lambda + mu) H(phi) c
// (u = 0 on the boundary).
#include "fem_test_utilities.h"

#include <deal.II/base/function.h>
#include <deal.II/numerics/vector_tools.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::fem {
namespace {

using dealii::Point;
using dealii::Tensor;

constexpr double pi = M_PI;
const double c_vec[3] = {1e-3, 2e-3, 3e-3};

double phi(const Point<3>& p) {
  return std::sin(pi * p[0]) * std::sin(pi * p[1]) * std::sin(pi * p[2]);
}

// Hessian of phi.
Tensor<2, 3> phi_hessian(const Point<3>& p) {
  Tensor<2, 3> h;
  const double s[3] = {std::sin(pi * p[0]), std::sin(pi * p[1]), std::sin(pi * p[2])};
  const double c[3] = {std::cos(pi * p[0]), std::cos(pi * p[1]), std::cos(pi * p[2])};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == j)
        h[i][j] = -pi * pi * s[0] * s[1] * s[2];
      else {
        const int k = 3 - i - j;
        h[i][j] = pi * pi * c[i] * c[j] * s[k];
      }
    }
  return h;
}

class Exact : public dealii::Function<3> {
public:
  Exact() : dealii::Function<3>(3) {}
  double value(const Point<3>& p, unsigned int component) const override {
    return c_vec[component] * phi(p);
  }
  Tensor<1, 3> gradient(const Point<3>& p, unsigned int component) const override {
    Tensor<1, 3> g;
    g[0] = pi * std::cos(pi * p[0]) * std::sin(pi * p[1]) * std::sin(pi * p[2]);
    g[1] = pi * std::sin(pi * p[0]) * std::cos(pi * p[1]) * std::sin(pi * p[2]);
    g[2] = pi * std::sin(pi * p[0]) * std::sin(pi * p[1]) * std::cos(pi * p[2]);
    return c_vec[component] * g;
  }
};

class BodyForce : public dealii::Function<3> {
public:
  BodyForce(double lambda, double mu) : dealii::Function<3>(3), lambda_(lambda), mu_(mu) {}
  double value(const Point<3>& p, unsigned int component) const override {
    const Tensor<2, 3> h = phi_hessian(p);
    double hc = 0;
    for (int j = 0; j < 3; ++j)
      hc += h[component][j] * c_vec[j];
    return 3 * pi * pi * mu_ * c_vec[component] * phi(p) - (lambda_ + mu_) * hc;
  }

private:
  double lambda_, mu_;
};

struct Row {
  unsigned int n;
  double h, l2, h1;
};

std::vector<Row> convergence(CellKind kind, unsigned int degree, std::vector<unsigned int> sizes) {
  const LinearElasticMaterial material(1e6, 0.3);
  const MaterialTable materials(material);
  const Discretization disc(kind, degree);
  const Exact exact;
  const BodyForce force(material.lambda(), material.mu());
  std::vector<Row> rows;
  for (const unsigned int n : sizes) {
    dealii::Triangulation<3> tria;
    testing::make_box(tria, kind, n, n, n, 1, 1, 1);
    LinearElasticity problem(tria, disc, materials);
    std::map<dealii::types::boundary_id, const dealii::Function<3>*> dirichlet;
    for (dealii::types::boundary_id b = 0; b < 6; ++b)
      dirichlet[b] = nullptr;
    problem.setup(dirichlet);
    problem.assemble(&force);
    problem.solve();
    const auto [l2, h1] = problem.errors(exact);
    rows.push_back({n, 1.0 / n, l2, h1});
  }
  std::printf("\n%s convergence (manufactured solution, E = 1 MPa, nu = 0.3)\n",
              disc.name().c_str());
  std::printf("%6s %12s %10s %12s %10s\n", "cells/e", "L2 error", "L2 rate", "H1 error", "H1 rate");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (i == 0)
      std::printf("%6u %12.4e %10s %12.4e %10s\n", rows[i].n, rows[i].l2, "-", rows[i].h1, "-");
    else
      std::printf("%6u %12.4e %10.3f %12.4e %10.3f\n", rows[i].n, rows[i].l2,
                  std::log2(rows[i - 1].l2 / rows[i].l2), rows[i].h1,
                  std::log2(rows[i - 1].h1 / rows[i].h1));
  }
  return rows;
}

void expect_rates(const std::vector<Row>& rows, double l2_rate, double h1_rate) {
  ASSERT_GE(rows.size(), 3u);
  const std::size_t last = rows.size() - 1;
  const double observed_l2 = std::log2(rows[last - 1].l2 / rows[last].l2);
  const double observed_h1 = std::log2(rows[last - 1].h1 / rows[last].h1);
  EXPECT_NEAR(observed_l2, l2_rate, 0.2);
  EXPECT_NEAR(observed_h1, h1_rate, 0.2);
}

TEST(Convergence, P1) {
  expect_rates(convergence(CellKind::tetrahedron, 1, {4, 8, 16}), 2, 1);
}
TEST(Convergence, P2) {
  expect_rates(convergence(CellKind::tetrahedron, 2, {2, 4, 8}), 3, 2);
}
TEST(Convergence, Q1) {
  expect_rates(convergence(CellKind::hexahedron, 1, {4, 8, 16}), 2, 1);
}
TEST(Convergence, Q2) {
  expect_rates(convergence(CellKind::hexahedron, 2, {2, 4, 8}), 3, 2);
}

} // namespace
} // namespace plantar::fem
