// CondensedSole is exact to solver round-off (coupling/condensed_sole.h):
//  - C against the dense Schur complement inverse (K_cc - K_cn K_nn^-1 K_nc)^-1
//    built from the sparse K with Eigen dense Cholesky: relative error < 1e-10;
//  - u_c = C f and the recovered interior u_n against a full FEM solve with
//    UMFPACK (fem::LinearSolver, a different factorization library than the
//    CHOLMOD one inside CondensedSole) for random contact forces: < 1e-10;
//  - C symmetric (before symmetrization, < 1e-12) and positive definite;
//  - consistent contact loads sum to traction x area (1e-12);
//  - for P1, P2, Q1, Q2 boxes and the real sole mesh (gmsh, P1 tetrahedra
//    and Q1 hexahedra, coarse).
#include "condensation_test_utilities.h"

#include "fem/linear_solver.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>

namespace plantar::coupling {
namespace {

using testing::max_abs;

constexpr double youngs_modulus = 4e6, poisson_ratio = 0.3; // the paper's sole

struct Check {
  double compliance_error, stiffness_error, displacement_error, interior_error, asymmetry,
      min_eigenvalue, condition;
};

// Compares @p sole against the dense reference and a full UMFPACK solve.
Check check_exact(const CondensedSole& sole, unsigned int seed) {
  Check result{};
  const int n_c = sole.n_contacts();
  // Dense reference: K_FF from the sparse matrix, split c | n, Schur complement.
  std::vector<unsigned int> free_dofs;
  const Eigen::MatrixXd k_ff = testing::dense_free_stiffness(sole, free_dofs);
  std::vector<int> position(sole.n_dofs(), -1);
  for (std::size_t i = 0; i < free_dofs.size(); ++i)
    position[free_dofs[i]] = static_cast<int>(i);
  std::vector<int> c_index, n_index;
  std::vector<bool> is_contact(free_dofs.size(), false);
  for (const auto& node : sole.contact_dofs())
    for (int d = 0; d < 3; ++d) {
      c_index.push_back(position[node[d]]);
      is_contact[position[node[d]]] = true;
    }
  for (std::size_t i = 0; i < free_dofs.size(); ++i)
    if (!is_contact[i])
      n_index.push_back(static_cast<int>(i));
  const Eigen::MatrixXd k_cc = k_ff(c_index, c_index), k_cn = k_ff(c_index, n_index),
                        k_nn = k_ff(n_index, n_index);
  const Eigen::LLT<Eigen::MatrixXd> k_nn_llt(k_nn);
  const Eigen::MatrixXd k_c = k_cc - k_cn * k_nn_llt.solve(k_cn.transpose());
  const Eigen::MatrixXd c_dense = k_c.llt().solve(Eigen::MatrixXd::Identity(3 * n_c, 3 * n_c));
  result.compliance_error = max_abs(sole.compliance() - c_dense) / max_abs(c_dense);
  result.stiffness_error =
      sole.stiffness().size() == 0 ? -1 : max_abs(sole.stiffness() - k_c) / max_abs(k_c);
  result.asymmetry = sole.raw_asymmetry();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(sole.compliance(),
                                                             Eigen::EigenvaluesOnly);
  result.min_eigenvalue = eigen.eigenvalues().minCoeff();
  result.condition = eigen.eigenvalues().maxCoeff() / result.min_eigenvalue;

  // Full solve with UMFPACK for random contact forces (N).
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd forces(3 * n_c);
  for (auto& value : forces)
    value = 10.0 * uniform(generator);
  dealii::Vector<double> rhs(sole.n_dofs()), full(sole.n_dofs());
  for (int k = 0; k < n_c; ++k)
    for (int d = 0; d < 3; ++d)
      rhs(sole.contact_dofs()[k][d]) = forces(3 * k + d);
  fem::LinearSolver umfpack{fem::LinearSolverSettings{}};
  umfpack.initialize(sole.elasticity().stiffness_matrix());
  umfpack.solve(rhs, full);
  sole.elasticity().constraints().distribute(full);
  const Eigen::VectorXd u_c = sole.compliance() * forces;
  Eigen::VectorXd u_c_full(3 * n_c);
  for (int k = 0; k < n_c; ++k)
    for (int d = 0; d < 3; ++d)
      u_c_full(3 * k + d) = full(sole.contact_dofs()[k][d]);
  result.displacement_error = (u_c - u_c_full).norm() / u_c_full.norm();
  dealii::Vector<double> recovered;
  sole.recover(u_c, recovered);
  dealii::Vector<double> difference = recovered;
  difference -= full;
  result.interior_error = difference.l2_norm() / full.l2_norm();
  return result;
}

void print_and_assert(const std::string& label, const CondensedSole& sole, const Check& check) {
  char stiffness_text[32] = "not stored";
  if (check.stiffness_error >= 0)
    std::snprintf(stiffness_text, sizeof(stiffness_text), "%.2e", check.stiffness_error);
  std::printf("%-26s n_c %4d dofs %6d | C vs dense %.2e | K_c vs dense %10s | u_c vs UMFPACK "
              "%.2e | field %.2e | asym %.1e | eig_min %.3e m/N cond %.2e\n",
              label.c_str(), sole.n_contacts(), sole.n_dofs(), check.compliance_error,
              stiffness_text, check.displacement_error, check.interior_error, check.asymmetry,
              check.min_eigenvalue, check.condition);
  EXPECT_LT(check.compliance_error, 1e-10) << label;
  EXPECT_LT(check.displacement_error, 1e-10) << label;
  EXPECT_LT(check.interior_error, 1e-10) << label;
  EXPECT_LT(check.asymmetry, 1e-12) << label;
  EXPECT_GT(check.min_eigenvalue, 0.0) << label;
  // K_c = C^-1 loses about cond(C) * eps to the inversion.
  if (check.stiffness_error >= 0) {
    EXPECT_LT(check.stiffness_error, 1e-13 * check.condition + 1e-12) << label;
  }
}

void check_load_sum(const CondensedSole& sole, double area, const std::string& label) {
  const Eigen::Vector3d traction(1e3, -2e3, 5e4);
  Eigen::VectorXd forces(3 * sole.n_contacts());
  sole.contact_load(traction, forces);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int k = 0; k < sole.n_contacts(); ++k)
    total += forces.segment<3>(3 * k);
  const double error = (total - traction * area).norm() / (traction * area).norm();
  std::printf("%-26s contact load sum vs t A: relative error %.2e (area %.6f m^2)\n", label.c_str(),
              error, area);
  EXPECT_LT(error, 1e-12) << label;
}

struct BoxCase {
  fem::CellKind kind;
  unsigned int degree, n_x, n_y, n_z;
  int expected_contacts; // -1: not checked
};

TEST(Condensation, BoxesAgainstDenseSchurAndFullSolve) {
  const double a = 0.06, b = 0.04, c = 0.02;
  const BoxCase cases[] = {{fem::CellKind::tetrahedron, 1, 3, 2, 2, 12},
                           {fem::CellKind::tetrahedron, 2, 2, 2, 1, -1},
                           {fem::CellKind::hexahedron, 1, 4, 3, 2, 20},
                           {fem::CellKind::hexahedron, 1, 3, 2, 1, 12}, // no interior dofs
                           {fem::CellKind::hexahedron, 2, 2, 2, 2, 25}};
  const fem::MaterialTable materials(fem::LinearElasticMaterial(youngs_modulus, poisson_ratio));
  std::printf("\n");
  unsigned int seed = 1;
  for (const auto& box : cases) {
    dealii::Triangulation<3> tria;
    testing::make_sole_box(tria, box.kind, box.n_x, box.n_y, box.n_z, a, b, c);
    CondensationParameters parameters;
    parameters.attached_boundary = 0;
    parameters.contact_boundary = 1;
    parameters.degree = box.degree;
    parameters.block_size = 7; // exercises partial blocks
    parameters.compute_stiffness = true;
    const CondensedSole sole(tria, materials, parameters);
    const std::string label = fem::Discretization(box.kind, box.degree).name() + " box " +
                              std::to_string(box.n_x) + "x" + std::to_string(box.n_y) + "x" +
                              std::to_string(box.n_z);
    if (box.expected_contacts >= 0) {
      EXPECT_EQ(sole.n_contacts(), box.expected_contacts) << label;
    }
    EXPECT_LT((sole.contact_positions().col(2).array() + c).abs().maxCoeff(), 1e-12 * c)
        << label << ": a contact node is off the bottom face";
    print_and_assert(label, sole, check_exact(sole, seed++));
    check_load_sum(sole, a * b, label);
  }
}

TEST(Condensation, RealSoleMeshCoarse) {
  // meshes/sole_box.geo, HRP-2 outline 0.2172 x 0.138 x 0.02 m.
  const double length = 0.2172, width = 0.138;
  std::printf("\n");
  for (const double hex : {0.0, 1.0}) {
    dealii::Triangulation<3> tria;
    const auto groups = testing::load_sole_mesh(
        tria, {{"SoleMeshSize", hex > 0 ? 0.015 : 0.035}, {"SoleHex", hex}});
    const fem::MaterialTable materials(
        fem::LinearElasticMaterial(youngs_modulus, poisson_ratio, "rubber"));
    CondensationParameters parameters;
    parameters.attached_boundary = groups.surface("top");
    parameters.contact_boundary = groups.surface("bottom");
    const CondensedSole sole(tria, materials, parameters);
    const std::string label = hex > 0 ? "sole_box.geo Q1 h=0.015" : "sole_box.geo P1 h=0.035";
    if (hex > 0) { // Ceil(0.2172 / 0.015) = 15 by Ceil(0.138 / 0.015) = 10 cells: 16 x 11 nodes
      EXPECT_EQ(sole.n_contacts(), 176);
    }
    print_and_assert(label, sole, check_exact(sole, 42));
    check_load_sum(sole, length * width, label);
  }
}

TEST(Condensation, WritesRecoveredField) {
  dealii::Triangulation<3> tria;
  testing::make_sole_box(tria, fem::CellKind::hexahedron, 3, 2, 2, 0.06, 0.04, 0.02);
  const fem::MaterialTable materials(fem::LinearElasticMaterial(youngs_modulus, poisson_ratio));
  const CondensedSole sole(tria, materials, CondensationParameters{});
  Eigen::VectorXd forces(3 * sole.n_contacts());
  sole.contact_load(Eigen::Vector3d(0, 0, 1e4), forces);
  const Eigen::VectorXd u_c = sole.compliance() * forces;
  const auto path = std::filesystem::current_path() / "condensation_field.vtu";
  std::filesystem::remove(path);
  sole.write_vtu(u_c, path);
  ASSERT_TRUE(std::filesystem::exists(path));
  // The written field is the recovered one: its largest |u| is the largest
  // recovered nodal displacement, all upward (compression) at the bottom.
  dealii::Vector<double> field;
  sole.recover(u_c, field);
  std::printf("\nwrote %s (%ju bytes), max |u_i| %.3e m, min u_z at contact %.3e m\n", path.c_str(),
              static_cast<std::uintmax_t>(std::filesystem::file_size(path)), field.linfty_norm(),
              u_c(Eigen::seqN(2, sole.n_contacts(), 3)).minCoeff());
  EXPECT_GT(std::filesystem::file_size(path), 1000u);
  EXPECT_GT(u_c(Eigen::seqN(2, sole.n_contacts(), 3)).minCoeff(), 0.0);
  EXPECT_NEAR(field.linfty_norm(), u_c.cwiseAbs().maxCoeff(), 1e-12 * field.linfty_norm());
}

TEST(Condensation, RejectsBadInput) {
  dealii::Triangulation<3> tria;
  testing::make_sole_box(tria, fem::CellKind::hexahedron, 2, 2, 1, 0.06, 0.04, 0.02);
  const fem::MaterialTable materials(fem::LinearElasticMaterial(youngs_modulus, poisson_ratio));
  CondensationParameters parameters;
  parameters.degree = 3;
  EXPECT_THROW(CondensedSole(tria, materials, parameters), std::invalid_argument);
  parameters.degree = 1;
  parameters.block_size = 0;
  EXPECT_THROW(CondensedSole(tria, materials, parameters), std::invalid_argument);
  parameters.block_size = 64;
  parameters.contact_boundary = 7; // no such face
  EXPECT_THROW(CondensedSole(tria, materials, parameters), std::invalid_argument);
  parameters.contact_boundary = 2; // the sides touch the top: contact nodes would be attached
  EXPECT_THROW(CondensedSole(tria, materials, parameters), std::invalid_argument);
  parameters.contact_boundary = 1;
  const CondensedSole sole(tria, materials, parameters);
  dealii::Vector<double> field;
  EXPECT_THROW(sole.recover(Eigen::VectorXd::Zero(5), field), std::invalid_argument);
  try {
    parameters.block_size = 5000;
    CondensedSole bad(tria, materials, parameters);
    ADD_FAILURE() << "block_size 5000 accepted";
  } catch (const std::invalid_argument& error) {
    std::printf("message: %s\n", error.what());
    EXPECT_NE(std::string(error.what()).find("block_size = 5000"), std::string::npos);
  }
}

} // namespace
} // namespace plantar::coupling
