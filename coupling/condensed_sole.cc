#include "coupling/condensed_sole.h"

#include "contact/symmetry.h"
#include "fem/contact_condensation.h"
#include "fem/discretization.h"
#include "fem/field_output.h"
#include "fem/mesh_import.h"

#include <deal.II/fe/fe_values.h>

#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace plantar::coupling {

using dealii::types::global_dof_index;
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Cholesky = Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::size_t sparse_bytes(const SparseMatrix& matrix) {
  return static_cast<std::size_t>(matrix.nonZeros()) * (sizeof(double) + sizeof(int)) +
         static_cast<std::size_t>(matrix.outerSize() + 1) * sizeof(int);
}

/// Factorizes @p matrix (SPD); throws std::runtime_error naming @p what otherwise.
void factorize(Cholesky& cholesky, const SparseMatrix& matrix, const std::string& what) {
  cholesky.compute(matrix);
  if (cholesky.info() != Eigen::Success)
    throw std::runtime_error(
        "CondensedSole: the Cholesky factorization of " + what + " (" +
        std::to_string(matrix.rows()) +
        " dofs) failed: the matrix is not positive definite (is the attached boundary empty, "
        "or is a material parameter out of range?)");
}

unsigned int count_faces(const dealii::Triangulation<3>& triangulation,
                         dealii::types::boundary_id boundary) {
  unsigned int n_faces = 0;
  for (const auto& cell : triangulation.active_cell_iterators())
    for (const auto& face : cell->face_iterators())
      if (face->at_boundary() && face->boundary_id() == boundary)
        ++n_faces;
  return n_faces;
}

} // namespace

void CondensationParameters::validate() const {
  if (degree != 1 && degree != 2)
    throw std::invalid_argument("CondensationParameters.degree = " + std::to_string(degree) +
                                " is out of range (allowed: 1 or 2)");
  if (block_size < 1 || block_size > 4096)
    throw std::invalid_argument("CondensationParameters.block_size = " +
                                std::to_string(block_size) + " is out of range [1, 4096]");
  if (form == Form::factorization && compute_stiffness)
    throw std::invalid_argument("CondensationParameters: compute_stiffness needs form = dense "
                                "(K_c = C^-1 is formed from C)");
  if (attached_boundary == contact_boundary)
    throw std::invalid_argument(
        "CondensationParameters: attached_boundary and contact_boundary are both " +
        std::to_string(attached_boundary) + " (they must differ)");
}

struct CondensedSole::Impl {
  Impl(const dealii::Triangulation<3>& source, const fem::MaterialTable& material_table,
       unsigned int degree)
      : materials(material_table) {
    triangulation.copy_triangulation(source);
    discretization = std::make_unique<fem::Discretization>(fem::cell_kind(triangulation), degree);
    elasticity = std::make_unique<fem::LinearElasticity>(triangulation, *discretization, materials);
  }

  dealii::Triangulation<3> triangulation;
  fem::MaterialTable materials;
  std::unique_ptr<fem::Discretization> discretization;
  std::unique_ptr<fem::LinearElasticity> elasticity;
  std::vector<int> dof_to_contact;        // global dof -> 3 k + d, or -1
  std::vector<global_dof_index> interior; // interior index -> global dof
  SparseMatrix k_nc;                      // (n_n x 3 n_c), N/m (Form::dense)
  std::unique_ptr<Cholesky> k_nn_factor;  // Cholesky of K_nn (Form::dense)
  // Form::factorization: the Cholesky of the free-dof K, the free dofs' global indices, and
  // the free index of contact dof 3 k + d.
  std::unique_ptr<Cholesky> k_ff_factor = std::make_unique<Cholesky>();
  bool factor_released = false;
  std::vector<global_dof_index> free_dofs;
  std::vector<unsigned int> contact_free;
};

CondensedSole::CondensedSole(CondensedSole&&) noexcept = default;
CondensedSole& CondensedSole::operator=(CondensedSole&&) noexcept = default;
CondensedSole::~CondensedSole() = default;

CondensedSole::CondensedSole(const dealii::Triangulation<3>& triangulation,
                             const fem::MaterialTable& materials,
                             const CondensationParameters& parameters)
    : parameters_(parameters) {
  parameters_.validate();
  for (const auto& [name, id] : {std::pair{"attached_boundary", parameters_.attached_boundary},
                                 std::pair{"contact_boundary", parameters_.contact_boundary}})
    if (count_faces(triangulation, id) == 0)
      throw std::invalid_argument(std::string("CondensedSole: CondensationParameters.") + name +
                                  " = " + std::to_string(id) +
                                  " names no boundary face of the mesh");

  // 1. Assembly of K (Dirichlet rows of the attached face eliminated).
  auto start = std::chrono::steady_clock::now();
  impl_ = std::make_unique<Impl>(triangulation, materials, parameters_.degree);
  fem::LinearElasticity& elasticity = *impl_->elasticity;
  elasticity.setup({{parameters_.attached_boundary, nullptr}});
  elasticity.assemble();
  const auto& constraints = elasticity.constraints();
  const dealii::SparseMatrix<double>& k_full = elasticity.stiffness_matrix();
  const global_dof_index n_dofs = elasticity.dof_handler().n_dofs();
  for (global_dof_index dof = 0; dof < n_dofs; ++dof)
    if (constraints.is_constrained(dof) && (constraints.is_inhomogeneously_constrained(dof) ||
                                            !constraints.get_constraint_entries(dof)->empty()))
      throw std::runtime_error("CondensedSole: dof " + std::to_string(dof) +
                               " carries a constraint other than u = 0 (hanging nodes or "
                               "inhomogeneous Dirichlet data are not supported)");

  // Contact nodes, their positions, and the split of the free dofs.
  contact_dofs_ = elasticity.boundary_nodes(parameters_.contact_boundary);
  const int n_c = static_cast<int>(contact_dofs_.size());
  const auto points = elasticity.support_points();
  fem::check_contact_nodes_free(contact_dofs_, constraints, points, parameters_.attached_boundary,
                                "CondensedSole");
  contact_positions_.resize(n_c, 3);
  impl_->dof_to_contact.assign(n_dofs, -1);
  for (int k = 0; k < n_c; ++k)
    for (int d = 0; d < 3; ++d) {
      const global_dof_index dof = contact_dofs_[k][d];
      impl_->dof_to_contact[dof] = 3 * k + d;
      contact_positions_(k, d) = points[dof][d];
    }
  std::vector<int> free_index(n_dofs, -1);     // global -> free (K_FF) index
  std::vector<int> interior_index(n_dofs, -1); // global -> interior (K_nn) index
  int n_free = 0;
  for (global_dof_index dof = 0; dof < n_dofs; ++dof)
    if (!constraints.is_constrained(dof)) {
      free_index[dof] = n_free++;
      if (impl_->dof_to_contact[dof] < 0) {
        interior_index[dof] = static_cast<int>(impl_->interior.size());
        impl_->interior.push_back(dof);
      }
    }
  const int n_n = static_cast<int>(impl_->interior.size());

  // Free-dof K (CSC) and its K_nn, K_nc blocks, from deal.II's CSR rows.
  std::vector<Eigen::Triplet<double, int>> k_ff_entries, k_nn_entries, k_nc_entries, k_cc_entries;
  k_ff_entries.reserve(k_full.n_nonzero_elements());
  for (global_dof_index row = 0; row < n_dofs; ++row) {
    if (free_index[row] < 0)
      continue;
    for (auto entry = k_full.begin(row); entry != k_full.end(row); ++entry) {
      const global_dof_index col = entry->column();
      if (free_index[col] < 0 || entry->value() == 0.0)
        continue;
      k_ff_entries.emplace_back(free_index[row], free_index[col], entry->value());
      if (interior_index[row] >= 0 && interior_index[col] >= 0)
        k_nn_entries.emplace_back(interior_index[row], interior_index[col], entry->value());
      else if (interior_index[row] >= 0)
        k_nc_entries.emplace_back(interior_index[row], impl_->dof_to_contact[col], entry->value());
      else if (interior_index[col] < 0)
        k_cc_entries.emplace_back(impl_->dof_to_contact[row], impl_->dof_to_contact[col],
                                  entry->value());
    }
  }
  SparseMatrix k_ff(n_free, n_free);
  k_ff.setFromTriplets(k_ff_entries.begin(), k_ff_entries.end());
  k_ff_entries = {};
  timings_.assembly = seconds_since(start);

  const bool dense = parameters_.form == CondensationParameters::Form::dense;
  impl_->contact_free.resize(3 * n_c); // free index of contact dof i
  for (int k = 0; k < n_c; ++k)
    for (int d = 0; d < 3; ++d)
      impl_->contact_free[3 * k + d] = static_cast<unsigned int>(free_index[contact_dofs_[k][d]]);

  // 2. C = [K^-1]_cc: one factorization, 3 n_c solves in blocks of unit vectors; or the
  // factorization kept (Form::factorization).
  if (!dense) {
    start = std::chrono::steady_clock::now();
    factorize(*impl_->k_ff_factor, k_ff, "the free-dof stiffness K");
    memory_.condensation_factorization_bytes = impl_->k_ff_factor->cholmod().memory_inuse;
    timings_.factorization = seconds_since(start);
    impl_->free_dofs.reserve(n_free);
    for (global_dof_index dof = 0; dof < n_dofs; ++dof)
      if (free_index[dof] >= 0)
        impl_->free_dofs.push_back(dof);
  } else {
    start = std::chrono::steady_clock::now();
    Cholesky k_ff_factor;
    factorize(k_ff_factor, k_ff, "the free-dof stiffness K");
    memory_.condensation_factorization_bytes = k_ff_factor.cholmod().memory_inuse;
    timings_.factorization = seconds_since(start);

    start = std::chrono::steady_clock::now();
    const int n_rows = 3 * n_c;
    const std::vector<unsigned int>& contact_free = impl_->contact_free;
    // CHOLMOD reads the right-hand sides in place (Eigen::Ref of the map: no copy).
    const fem::BlockSolve solve = [&](const double* rhs, double* solution, unsigned int count) {
      Eigen::Map<Eigen::MatrixXd>(solution, n_free, count) =
          k_ff_factor.solve(Eigen::Map<const Eigen::MatrixXd>(rhs, n_free, count));
    };
    compliance_.resize(n_rows, n_rows);
    fem::contact_block_of_inverse(contact_free, static_cast<unsigned int>(n_free),
                                  static_cast<unsigned int>(parameters_.block_size), solve,
                                  compliance_.data(), "CondensedSole");
    timings_.contact_solves = seconds_since(start);
    raw_asymmetry_ = contact::relative_asymmetry(compliance_);
    fem::symmetrize(compliance_.data(), static_cast<unsigned int>(compliance_.rows()));
  }

  // 3. Recovery operator: Cholesky of K_nn, and K_nc (released after step 4 with
  // Form::factorization).
  start = std::chrono::steady_clock::now();
  {
    SparseMatrix k_nn(n_n, n_n);
    k_nn.setFromTriplets(k_nn_entries.begin(), k_nn_entries.end());
    k_nn_entries = {};
    impl_->k_nc.resize(n_n, 3 * n_c);
    impl_->k_nc.setFromTriplets(k_nc_entries.begin(), k_nc_entries.end());
    k_nc_entries = {};
    if (n_n > 0) { // a one-layer Q1 sole has no interior dofs
      impl_->k_nn_factor = std::make_unique<Cholesky>();
      factorize(*impl_->k_nn_factor, k_nn, "the interior stiffness K_nn");
    }
  }
  timings_.recovery_factorization = seconds_since(start);

  // 4. K_R = R^T K_c R with K_c R = K_cc R + K_cn x_n, x_n = -K_nn^-1 K_nc R (6 solves).
  {
    SparseMatrix k_cc(3 * n_c, 3 * n_c);
    k_cc.setFromTriplets(k_cc_entries.begin(), k_cc_entries.end());
    k_cc_entries = {};
    const Eigen::Vector3d origin = contact_positions_.colwise().mean().transpose();
    Eigen::MatrixXd r = Eigen::MatrixXd::Zero(3 * n_c, 6);
    for (int k = 0; k < n_c; ++k) {
      const Eigen::Vector3d d = contact_positions_.row(k).transpose() - origin;
      r.block<3, 3>(3 * k, 0).setIdentity();
      r.block<3, 3>(3 * k, 3) << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;
    }
    Eigen::MatrixXd k_c_r = k_cc * r;
    if (n_n > 0) {
      const Eigen::MatrixXd x_n = impl_->k_nn_factor->solve(-(impl_->k_nc * r));
      k_c_r += impl_->k_nc.transpose() * x_n;
    }
    const Eigen::Matrix<double, 6, 6> k_r = r.transpose() * k_c_r;
    rigid_stiffness_ = 0.5 * (k_r + k_r.transpose());
    rigid_forces_ = std::move(k_c_r);
  }
  if (!dense) { // the factor of K recovers the fields
    impl_->k_nn_factor.reset();
    impl_->k_nc = SparseMatrix();
  }

  // 5. Optional K_c = C^-1.
  if (parameters_.compute_stiffness) {
    start = std::chrono::steady_clock::now();
    Eigen::LLT<Eigen::MatrixXd> llt(compliance_);
    if (llt.info() != Eigen::Success)
      throw std::runtime_error("CondensedSole: C is not positive definite (Cholesky failed), "
                               "cannot form K_c = C^-1");
    stiffness_ = llt.solve(Eigen::MatrixXd::Identity(3 * n_c, 3 * n_c));
    timings_.stiffness = seconds_since(start);
  }

  memory_.compliance_bytes = static_cast<std::size_t>(compliance_.size()) * sizeof(double);
  memory_.stiffness_bytes = static_cast<std::size_t>(stiffness_.size()) * sizeof(double);
  memory_.recovery_factorization_bytes =
      !dense ? memory_.condensation_factorization_bytes
             : (n_n > 0 ? impl_->k_nn_factor->cholmod().memory_inuse : 0);
  memory_.sparse_matrix_bytes = sparse_bytes(impl_->k_nc) + k_full.memory_consumption() +
                                k_full.get_sparsity_pattern().memory_consumption();
}

int CondensedSole::n_dofs() const {
  return static_cast<int>(impl_->elasticity->dof_handler().n_dofs());
}

const fem::LinearElasticity& CondensedSole::elasticity() const {
  return *impl_->elasticity;
}

void CondensedSole::recover(const Eigen::Ref<const Eigen::VectorXd>& contact_displacement,
                            dealii::Vector<double>& displacement) const {
  if (contact_displacement.size() != 3 * n_contacts())
    throw std::invalid_argument("CondensedSole::recover: contact displacement has size " +
                                std::to_string(contact_displacement.size()) +
                                ", expected 3 n_c = " + std::to_string(3 * n_contacts()));
  if (parameters_.form != CondensationParameters::Form::dense)
    throw std::logic_error("CondensedSole::recover: needs form = dense (the factorization form "
                           "recovers fields from forces: displacement_of_forces)");
  displacement.reinit(impl_->elasticity->dof_handler().n_dofs()); // zero: attached dofs
  if (!impl_->interior.empty()) {
    const Eigen::VectorXd rhs = -(impl_->k_nc * contact_displacement);
    const Eigen::VectorXd interior = impl_->k_nn_factor->solve(rhs);
    for (std::size_t i = 0; i < impl_->interior.size(); ++i)
      displacement(impl_->interior[i]) = interior(static_cast<Eigen::Index>(i));
  }
  for (int k = 0; k < n_contacts(); ++k)
    for (int d = 0; d < 3; ++d)
      displacement(contact_dofs_[k][d]) = contact_displacement(3 * k + d);
}

Eigen::MatrixXd CondensedSole::projected_compliance(const SparseMatrix& aggregation) const {
  const int n = 3 * n_contacts();
  if (aggregation.rows() != n)
    throw std::invalid_argument("CondensedSole::projected_compliance: the aggregation has " +
                                std::to_string(aggregation.rows()) +
                                " rows, expected 3 n_c = " + std::to_string(n));
  const int m = static_cast<int>(aggregation.cols());
  Eigen::MatrixXd result(m, m);
  if (parameters_.form == CondensationParameters::Form::dense) {
    const Eigen::MatrixXd ca = compliance_ * aggregation;
    result = aggregation.transpose() * ca;
  } else {
    if (!has_solver())
      throw std::logic_error("CondensedSole::projected_compliance: the factorization was released");
    // Blocks of columns of B A solved at once; C A's columns are their contact rows.
    const Eigen::Index n_free = static_cast<Eigen::Index>(impl_->free_dofs.size());
    const int block = std::max(1, std::min(parameters_.block_size, m));
    Eigen::MatrixXd rhs(n_free, block), x_c(n, block);
    for (int first = 0; first < m; first += block) {
      const int count = std::min(block, m - first);
      rhs.setZero();
      for (int j = 0; j < count; ++j)
        for (SparseMatrix::InnerIterator it(aggregation, first + j); it; ++it)
          rhs(impl_->contact_free[it.row()], j) = it.value();
      const Eigen::MatrixXd x = impl_->k_ff_factor->solve(rhs.leftCols(count));
      for (int i = 0; i < n; ++i)
        x_c.row(i).head(count) = x.row(impl_->contact_free[i]);
      result.middleCols(first, count) = aggregation.transpose() * x_c.leftCols(count);
    }
  }
  if (!result.allFinite())
    throw std::runtime_error("CondensedSole::projected_compliance: non-finite entries");
  return 0.5 * (result + result.transpose());
}

void CondensedSole::release_factorization() {
  if (parameters_.form != CondensationParameters::Form::factorization)
    return;
  impl_->k_ff_factor = std::make_unique<Cholesky>();
  impl_->factor_released = true;
  memory_.recovery_factorization_bytes = 0;
}

bool CondensedSole::has_solver() const {
  return parameters_.form == CondensationParameters::Form::dense || !impl_->factor_released;
}

void CondensedSole::displacement_of_forces(const Eigen::Ref<const Eigen::VectorXd>& contact_force,
                                           dealii::Vector<double>& displacement) const {
  if (contact_force.size() != 3 * n_contacts())
    throw std::invalid_argument("CondensedSole::displacement_of_forces: contact force has size " +
                                std::to_string(contact_force.size()) +
                                ", expected 3 n_c = " + std::to_string(3 * n_contacts()));
  if (parameters_.form == CondensationParameters::Form::dense) {
    recover(compliance_ * contact_force, displacement);
    return;
  }
  if (!has_solver())
    throw std::logic_error("CondensedSole::displacement_of_forces: the factorization was released");
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(impl_->free_dofs.size()));
  for (Eigen::Index i = 0; i < contact_force.size(); ++i)
    rhs(impl_->contact_free[i]) = contact_force(i);
  const Eigen::VectorXd x = impl_->k_ff_factor->solve(rhs);
  displacement.reinit(impl_->elasticity->dof_handler().n_dofs()); // zero: attached dofs
  for (std::size_t i = 0; i < impl_->free_dofs.size(); ++i)
    displacement(impl_->free_dofs[i]) = x(static_cast<Eigen::Index>(i));
}

void CondensedSole::contact_load(const Eigen::Vector3d& traction,
                                 Eigen::Ref<Eigen::VectorXd> forces) const {
  if (forces.size() != 3 * n_contacts())
    throw std::invalid_argument("CondensedSole::contact_load: forces has size " +
                                std::to_string(forces.size()) +
                                ", expected 3 n_c = " + std::to_string(3 * n_contacts()));
  forces.setZero();
  const fem::Discretization& disc = *impl_->discretization;
  const auto& fe = *disc.fe;
  dealii::FEFaceValues<3> fe_face(*disc.mapping, fe, disc.face_quadrature,
                                  dealii::update_values | dealii::update_JxW_values);
  std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
  for (const auto& cell : impl_->elasticity->dof_handler().active_cell_iterators())
    for (const unsigned int f : cell->face_indices())
      if (cell->face(f)->at_boundary() &&
          cell->face(f)->boundary_id() == parameters_.contact_boundary) {
        fe_face.reinit(cell, f);
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < dofs.size(); ++i) {
          const int index = impl_->dof_to_contact[dofs[i]];
          if (index < 0)
            continue; // not a contact dof: its shape function vanishes on the face
          const unsigned int component = fe.system_to_component_index(i).first;
          for (unsigned int q = 0; q < fe_face.n_quadrature_points; ++q)
            forces(index) += fe_face.shape_value(i, q) * traction(component) * fe_face.JxW(q);
        }
      }
}

void CondensedSole::write_vtu(const Eigen::Ref<const Eigen::VectorXd>& contact_displacement,
                              const std::filesystem::path& path) const {
  recover(contact_displacement, impl_->elasticity->solution());
  fem::write_vtu(*impl_->elasticity, path);
}

} // namespace plantar::coupling
