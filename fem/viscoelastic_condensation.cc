#include "fem/viscoelastic_condensation.h"

#include "fem/contact_condensation.h"
#include "fem/linear_elastic_material.h"

#include <deal.II/base/function.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/fe_values_extractors.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/numerics/vector_tools.h>

#include <umfpack.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace plantar::fem {

using namespace dealii;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

void ViscoelasticCondensationParameters::validate() const {
  std::ostringstream msg;
  if (!(time_step > 0.0) || !std::isfinite(time_step))
    msg << "ViscoelasticCondensationParameters.time_step = " << time_step
        << " s is out of range: allowed (0, inf)";
  else if (block_size < 1 || block_size > 4096)
    msg << "ViscoelasticCondensationParameters.block_size = " << block_size
        << " is out of range: allowed [1, 4096]";
  else if (attached_boundary == contact_boundary)
    msg << "ViscoelasticCondensationParameters: attached_boundary and contact_boundary are both "
        << attached_boundary;
  if (!msg.str().empty())
    throw std::invalid_argument(msg.str());
}

// The sparse LU of K_eff (UMFPACK, kept) with preallocated solve workspace, and the cell loop's
// FEValues and buffers: advance() allocates nothing.
struct ViscoelasticCondensation::Impl {
  std::vector<SuiteSparse_long> ap, ai; // K_eff rows (CSR; UMFPACK reads it as CSC of K^T)
  std::vector<double> ax;
  void* numeric = nullptr;
  double control[UMFPACK_CONTROL];
  double info[UMFPACK_INFO];
  std::vector<SuiteSparse_long> wi;
  std::vector<double> w;

  std::unique_ptr<FEValues<3>> fe_values; // set-up only (its reinit allocates)
  // The cell loop's geometry, kept so that advance() needs no FEValues: per (cell, q) the
  // inverse Jacobian d xi_k / d x_i and JxW; per (base function, q) the reference gradient.
  std::vector<Tensor<2, 3>> inverse_jacobian;
  std::vector<double> jxw;
  std::vector<Tensor<1, 3>> reference_gradient;
  std::vector<unsigned int> component, base; // per cell dof: its component and base function
  std::vector<Tensor<1, 3>> gradient;        // real gradients of the base functions at one q
  std::vector<types::global_dof_index> dofs;
  std::vector<double> local;
  Vector<double> cell_force;

  /// local = the solution's values at @p cell's dofs (dofs holds their indices).
  template <class CellIterator>
  void gather(const CellIterator& cell, const Vector<double>& solution) {
    cell->get_dof_indices(dofs);
    for (unsigned int j = 0; j < dofs.size(); ++j)
      local[j] = solution(dofs[j]);
  }

  ~Impl() {
    if (numeric)
      umfpack_dl_free_numeric(&numeric);
  }

  void factorize(const SparseMatrix<double>& matrix) {
    const auto n = static_cast<SuiteSparse_long>(matrix.m());
    ap.assign(n + 1, 0);
    ai.clear();
    ax.clear();
    std::vector<std::pair<SuiteSparse_long, double>> row;
    for (SuiteSparse_long r = 0; r < n; ++r) {
      row.clear();
      for (auto entry = matrix.begin(r); entry != matrix.end(r); ++entry)
        row.emplace_back(static_cast<SuiteSparse_long>(entry->column()), entry->value());
      std::sort(row.begin(), row.end());
      for (const auto& [column, value] : row) {
        ai.push_back(column);
        ax.push_back(value);
      }
      ap[r + 1] = static_cast<SuiteSparse_long>(ai.size());
    }
    umfpack_dl_defaults(control);
    control[UMFPACK_IRSTEP] = 0; // no iterative refinement: K_eff is SPD, the LU backward stable
    void* symbolic = nullptr;
    SuiteSparse_long status =
        umfpack_dl_symbolic(n, n, ap.data(), ai.data(), ax.data(), &symbolic, control, info);
    if (status == UMFPACK_OK)
      status =
          umfpack_dl_numeric(ap.data(), ai.data(), ax.data(), symbolic, &numeric, control, info);
    if (symbolic)
      umfpack_dl_free_symbolic(&symbolic);
    if (status != UMFPACK_OK)
      throw std::runtime_error("ViscoelasticCondensation: the LU factorization of K_eff failed "
                               "(UMFPACK status " +
                               std::to_string(status) +
                               "; singular: is the attached face clamping the sole?)");
    wi.resize(n);
    w.resize(5 * n);
  }

  /// K_eff x = b (both of size n); no allocation.
  void solve(const double* b, double* x) {
    const SuiteSparse_long status =
        umfpack_dl_wsolve(UMFPACK_Aat, ap.data(), ai.data(), ax.data(), x, b, numeric, control,
                          info, wi.data(), w.data());
    if (status != UMFPACK_OK)
      throw std::runtime_error("ViscoelasticCondensation: UMFPACK solve failed (status " +
                               std::to_string(status) + ")");
  }
};

ViscoelasticCondensation::ViscoelasticCondensation(
    const Triangulation<3>& triangulation, const Discretization& discretization,
    const ViscoelasticMaterialTable& materials,
    const ViscoelasticCondensationParameters& parameters)
    : triangulation_(triangulation), discretization_(discretization), materials_(materials),
      parameters_((parameters.validate(), parameters)), dof_handler_(triangulation),
      impl_(std::make_unique<Impl>()) {
  auto start = std::chrono::steady_clock::now();
  dof_handler_.distribute_dofs(*discretization_.fe);
  bool has_attached = false;
  for (const auto& face : triangulation.active_face_iterators())
    has_attached = has_attached ||
                   (face->at_boundary() && face->boundary_id() == parameters_.attached_boundary);
  if (!has_attached)
    throw std::invalid_argument("ViscoelasticCondensation: attached boundary id " +
                                std::to_string(parameters_.attached_boundary) + " has no face");
  const Functions::ZeroFunction<3> zero(3);
  VectorTools::interpolate_boundary_values(*discretization_.mapping, dof_handler_,
                                           parameters_.attached_boundary, zero, constraints_);
  constraints_.close();
  contact_dofs_ = boundary_nodes(dof_handler_, parameters_.contact_boundary);
  if (contact_dofs_.empty())
    throw std::invalid_argument("ViscoelasticCondensation: contact boundary id " +
                                std::to_string(parameters_.contact_boundary) + " has no face");
  std::vector<Point<3>> points(dof_handler_.n_dofs());
  DoFTools::map_dofs_to_support_points(*discretization_.mapping, dof_handler_, points);
  check_contact_nodes_free(contact_dofs_, constraints_, points, parameters_.attached_boundary,
                           "ViscoelasticCondensation");
  for (const auto& node : contact_dofs_)
    contact_positions_.push_back(points[node[0]]);

  // The step's constants per region, and the internal-variable layout per cell.
  const double dt = parameters_.time_step;
  for (const auto& cell : triangulation.active_cell_iterators()) {
    const types::material_id id = cell->material_id();
    if (regions_.count(id))
      continue;
    const ViscoelasticMaterial& material = materials_[id];
    RegionStep region;
    region.effective = material.effective_stiffness(dt);
    region.long_term = material.long_term_stiffness();
    region.effective_shear = material.shear_modulus();
    region.effective_bulk = material.bulk_modulus();
    for (const PronyBranch& branch : material.branches()) {
      double decay = 0, gamma = 0;
      ViscoelasticMaterial::step_factors(dt, branch.relaxation_time, decay, gamma);
      region.shear.push_back(branch.shear_modulus);
      region.bulk.push_back(branch.bulk_modulus);
      region.decay.push_back(decay);
      region.gamma.push_back(gamma);
      region.effective_shear += gamma * branch.shear_modulus;
      region.effective_bulk += gamma * branch.bulk_modulus;
      const double x = dt / branch.relaxation_time;
      double w_aa = 0, w_ac = 0, w_cc = 0;
      ViscoelasticMaterial::dissipation_weights(x, w_aa, w_ac, w_cc);
      region.w_aa.push_back(w_aa);
      region.w_ac.push_back(w_ac);
      region.w_cc.push_back(w_cc);
    }
    regions_.emplace(id, std::move(region));
  }
  check_separable();
  contact_space_ = separable_ && !parameters_.cell_dissipation;
  const unsigned int n_q = discretization_.cell_quadrature.size();
  cell_region_.resize(triangulation.n_active_cells());
  cell_history_.resize(triangulation.n_active_cells() + 1);
  std::size_t n_history = 0;
  for (const auto& cell : triangulation.active_cell_iterators()) {
    const RegionStep& region = regions_.at(cell->material_id());
    cell_region_[cell->active_cell_index()] = &region;
    cell_history_[cell->active_cell_index()] = n_history;
    if (!contact_space_)
      n_history += std::size_t{n_q} * region.decay.size();
  }
  history_.assign(n_history, SymmetricTensor<2, 3>());
  if (!contact_space_)
    strain_.assign(std::size_t{n_q} * triangulation.n_active_cells(), SymmetricTensor<2, 3>());

  const unsigned int n = dof_handler_.n_dofs();
  solution_.reinit(n);
  rhs_.reinit(n);
  history_force_.reinit(n);
  history_solution_.reinit(n);
  history_displacement_.reinit(3 * n_contacts());
  contact_displacement_.reinit(3 * n_contacts());
  previous_forces_.reinit(3 * n_contacts());
  if (contact_space_) {
    force_state_.reinit(3 * n_contacts());
    next_force_state_.reinit(3 * n_contacts());
    next_contact_displacement_.reinit(3 * n_contacts());
    branch_force_state_.assign(beta_.size(), Vector<double>(3 * n_contacts()));
    branch_contact_history_.assign(beta_.size(), Vector<double>(3 * n_contacts()));
  } else {
    cell_dissipation_.assign(triangulation.n_active_cells(), 0.0);
  }

  const auto& fe = *discretization_.fe;
  impl_->fe_values = std::make_unique<FEValues<3>>(
      *discretization_.mapping, fe, discretization_.cell_quadrature,
      update_gradients | update_JxW_values | update_inverse_jacobians);
  impl_->dofs.resize(fe.n_dofs_per_cell());
  impl_->local.resize(fe.n_dofs_per_cell());
  impl_->cell_force.reinit(fe.n_dofs_per_cell());
  store_geometry();

  assemble_effective_stiffness(); // and factorize
  timings_.assembly = seconds_since(start) - timings_.factorization;

  // C_eff = [K_eff^-1]_cc by unit-load solves with the same LU.
  start = std::chrono::steady_clock::now();
  std::vector<unsigned int> contact_index;
  for (const auto& node : contact_dofs_)
    for (const auto dof : node)
      contact_index.push_back(static_cast<unsigned int>(dof));
  const unsigned int size = 3 * n_contacts();
  compliance_.assign(std::size_t{size} * size, 0.0);
  contact_block_of_inverse(
      contact_index, n, parameters_.block_size,
      [this, n](const double* rhs, double* x, unsigned int count) {
        for (unsigned int j = 0; j < count; ++j)
          impl_->solve(rhs + std::size_t{j} * n, x + std::size_t{j} * n);
      },
      compliance_.data(), "ViscoelasticCondensation");
  raw_asymmetry_ = relative_asymmetry(compliance_.data(), size);
  symmetrize(compliance_.data(), size);
  timings_.condensation = seconds_since(start);
}

ViscoelasticCondensation::~ViscoelasticCondensation() = default;

unsigned int ViscoelasticCondensation::n_dofs() const {
  return dof_handler_.n_dofs();
}

void ViscoelasticCondensation::assemble_effective_stiffness() {
  DynamicSparsityPattern dsp(dof_handler_.n_dofs());
  DoFTools::make_sparsity_pattern(dof_handler_, dsp, constraints_, false);
  SparsityPattern sparsity;
  sparsity.copy_from(dsp);
  SparseMatrix<double> stiffness(sparsity);

  const auto& fe = *discretization_.fe;
  FEValues<3>& fe_values = *impl_->fe_values;
  const unsigned int n_dofs_cell = fe.n_dofs_per_cell();
  const unsigned int n_q = discretization_.cell_quadrature.size();
  FullMatrix<double> cell_matrix(n_dofs_cell, n_dofs_cell);
  std::vector<SymmetricTensor<2, 3>> eps_phi(n_dofs_cell);
  const FEValuesExtractors::Vector displacement(0);
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    cell_matrix = 0;
    const SymmetricTensor<4, 3>& C = cell_region_[cell->active_cell_index()]->effective;
    for (unsigned int q = 0; q < n_q; ++q) {
      for (unsigned int i = 0; i < n_dofs_cell; ++i)
        eps_phi[i] = fe_values[displacement].symmetric_gradient(i, q);
      const double JxW = fe_values.JxW(q);
      for (unsigned int i = 0; i < n_dofs_cell; ++i) {
        const SymmetricTensor<2, 3> C_eps_i = C * eps_phi[i];
        for (unsigned int j = 0; j <= i; ++j)
          cell_matrix(i, j) += (C_eps_i * eps_phi[j]) * JxW;
      }
    }
    for (unsigned int i = 0; i < n_dofs_cell; ++i)
      for (unsigned int j = i + 1; j < n_dofs_cell; ++j)
        cell_matrix(i, j) = cell_matrix(j, i);
    cell->get_dof_indices(impl_->dofs);
    constraints_.distribute_local_to_global(cell_matrix, impl_->dofs, stiffness);
  }
  const auto start = std::chrono::steady_clock::now();
  impl_->factorize(stiffness);
  timings_.factorization = seconds_since(start);
}

void ViscoelasticCondensation::advance(const Vector<double>& contact_forces,
                                       const Vector<double>* contact_displacement) {
  if (contact_forces.size() != 3 * n_contacts() ||
      (contact_displacement && contact_displacement->size() != 3 * n_contacts()))
    throw std::invalid_argument(
        "ViscoelasticCondensation::advance: " + std::to_string(contact_forces.size()) +
        " contact forces and " +
        std::to_string(contact_displacement ? contact_displacement->size() : 0) +
        " displacements (expected 3 n_c = " + std::to_string(3 * n_contacts()) + ")");
  if (contact_space_) {
    advance_contact_space(contact_forces, contact_displacement);
    return;
  }
  auto start = std::chrono::steady_clock::now();
  // K_eff u^{n+1} = P f - f_h^n.
  rhs_ = history_force_;
  rhs_ *= -1.0;
  for (unsigned int k = 0; k < n_contacts(); ++k)
    for (unsigned int d = 0; d < 3; ++d)
      rhs_(contact_dofs_[k][d]) += contact_forces(3 * k + d);
  impl_->solve(rhs_.begin(), solution_.begin());
  for (unsigned int k = 0; k < n_contacts(); ++k)
    for (unsigned int d = 0; d < 3; ++d) {
      const unsigned int i = 3 * k + d;
      const double u = solution_(contact_dofs_[k][d]);
      external_work_ +=
          0.5 * (previous_forces_(i) + contact_forces(i)) * (u - contact_displacement_(i));
      contact_displacement_(i) = u;
      previous_forces_(i) = contact_forces(i);
    }
  timings_.field_solve = seconds_since(start);
  start = std::chrono::steady_clock::now();
  update_history();
  time_ += parameters_.time_step;
  timings_.history = seconds_since(start);
}

void ViscoelasticCondensation::store_geometry() {
  const auto& fe = *discretization_.fe;
  const auto& base = fe.base_element(0);
  const auto& quadrature = discretization_.cell_quadrature;
  const unsigned int n_q = quadrature.size(), n_base = base.n_dofs_per_cell();
  Impl& w = *impl_;
  for (unsigned int j = 0; j < fe.n_dofs_per_cell(); ++j) {
    w.component.push_back(fe.system_to_component_index(j).first);
    w.base.push_back(fe.system_to_component_index(j).second);
  }
  w.reference_gradient.resize(std::size_t{n_base} * n_q);
  for (unsigned int b = 0; b < n_base; ++b)
    for (unsigned int q = 0; q < n_q; ++q)
      w.reference_gradient[std::size_t{b} * n_q + q] = base.shape_grad(b, quadrature.point(q));
  w.gradient.resize(n_base);
  w.inverse_jacobian.resize(std::size_t{n_q} * triangulation_.n_active_cells());
  w.jxw.resize(w.inverse_jacobian.size());
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    w.fe_values->reinit(cell);
    for (unsigned int q = 0; q < n_q; ++q) {
      const std::size_t k = std::size_t{cell->active_cell_index()} * n_q + q;
      const auto inverse = w.fe_values->inverse_jacobian(q);
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int i = 0; i < 3; ++i)
          w.inverse_jacobian[k][a][i] = inverse[a][i];
      w.jxw[k] = w.fe_values->JxW(q);
      // Check the stored map against FEValues' own gradients.
      for (unsigned int j = 0; j < fe.n_dofs_per_cell(); ++j) {
        const Tensor<1, 3> mine =
            w.reference_gradient[std::size_t{w.base[j]} * n_q + q] * w.inverse_jacobian[k];
        const Tensor<1, 3> theirs = w.fe_values->shape_grad_component(j, q, w.component[j]);
        if ((mine - theirs).norm() > 1e-10 * (theirs.norm() + 1.0 / cell->diameter()))
          throw std::logic_error("ViscoelasticCondensation: stored shape gradients differ "
                                 "from FEValues'");
      }
    }
  }
}

void ViscoelasticCondensation::update_history() {
  // Per quadrature point: h_i <- e_i h_i + gamma_i C_i : (eps^{n+1} - eps^n), then the next
  // step's history stress s = sum_i (e_i h_i - gamma_i C_i : eps^{n+1}) and f_h = int B^T s.
  // C_i : e = 2 G_i dev(e) + K_i tr(e) I.
  history_force_ = 0;
  Impl& w = *impl_;
  const unsigned int n_q = discretization_.cell_quadrature.size();
  const unsigned int n_dofs_cell = w.dofs.size();
  const unsigned int n_base = w.gradient.size();
  const SymmetricTensor<2, 3> identity = unit_symmetric_tensor<3>();
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    const unsigned int index = cell->active_cell_index();
    const RegionStep& region = *cell_region_[index];
    const std::size_t n_branches = region.decay.size();
    if (n_branches == 0)
      continue; // elastic region: no history
    w.gather(cell, solution_);
    w.cell_force = 0;
    SymmetricTensor<2, 3>* h = history_.data() + cell_history_[index];
    SymmetricTensor<2, 3>* strain = strain_.data() + std::size_t{index} * n_q;
    for (unsigned int q = 0; q < n_q; ++q) {
      const std::size_t k = std::size_t{index} * n_q + q;
      for (unsigned int b = 0; b < n_base; ++b) // grad phi = grad_xi phi . d xi / d x
        w.gradient[b] = w.reference_gradient[std::size_t{b} * n_q + q] * w.inverse_jacobian[k];
      Tensor<2, 3> grad_u;
      for (unsigned int j = 0; j < n_dofs_cell; ++j)
        grad_u[w.component[j]] += w.local[j] * w.gradient[w.base[j]];
      const SymmetricTensor<2, 3> eps = symmetrize(grad_u);
      const SymmetricTensor<2, 3> increment = eps - strain[q];
      const SymmetricTensor<2, 3> dev_increment = deviator(increment), dev_eps = deviator(eps);
      const double tr_increment = trace(increment), tr_eps = trace(eps);
      SymmetricTensor<2, 3> s;
      double dissipation = 0;
      for (std::size_t i = 0; i < n_branches; ++i, ++h) {
        const double e = region.decay[i], g = region.gamma[i];
        const double shear = region.shear[i], bulk = region.bulk[i];
        const SymmetricTensor<2, 3> c =
            2.0 * shear * dev_increment + (bulk * tr_increment) * identity;
        dissipation += region.w_aa[i] * inverse_product(*h, *h, shear, bulk) +
                       region.w_ac[i] * inverse_product(*h, c, shear, bulk) +
                       region.w_cc[i] * inverse_product(c, c, shear, bulk);
        *h = e * *h + g * c;
        s += e * *h - g * (2.0 * shear * dev_eps + (bulk * tr_eps) * identity);
      }
      cell_dissipation_[index] += dissipation * w.jxw[k];
      dissipated_energy_ += dissipation * w.jxw[k];
      strain[q] = eps;
      // f_j += (s : sym(e_c (x) grad phi_j)) JxW = (s . grad phi_j)_c JxW.
      const Tensor<2, 3> stress = s;
      for (unsigned int j = 0; j < n_dofs_cell; ++j)
        w.cell_force(j) += (stress[w.component[j]] * w.gradient[w.base[j]]) * w.jxw[k];
    }
    constraints_.distribute_local_to_global(w.cell_force, w.dofs, history_force_);
  }
  // d = -[K_eff^-1 f_h]_c, one back-substitution.
  impl_->solve(history_force_.begin(), history_solution_.begin());
  for (unsigned int k = 0; k < n_contacts(); ++k)
    for (unsigned int d = 0; d < 3; ++d)
      history_displacement_(3 * k + d) = -history_solution_(contact_dofs_[k][d]);
}

void ViscoelasticCondensation::check_separable() {
  // C_ri = beta_i C_eff,r: G_ri / G_eff,r = K_ri / K_eff,r = beta_i, the same in every region.
  auto near = [](double x, double y) {
    return std::abs(x - y) <= 1e-10 * std::max(std::abs(x), std::abs(y));
  };
  separable_ = true;
  beta_.clear();
  const RegionStep* first = nullptr;
  for (const auto& [id, region] : regions_) {
    (void)id;
    const std::size_t n_branches = region.decay.size();
    std::vector<double> beta(n_branches);
    for (std::size_t i = 0; i < n_branches; ++i) {
      const double shear = region.shear[i] / region.effective_shear;
      const double bulk = region.bulk[i] / region.effective_bulk;
      separable_ = separable_ && near(shear, bulk);
      beta[i] = shear;
    }
    if (first == nullptr) {
      first = &region;
      beta_ = beta;
      continue;
    }
    separable_ = separable_ && n_branches == first->decay.size();
    for (std::size_t i = 0; separable_ && i < n_branches; ++i)
      separable_ = near(beta[i], beta_[i]) && near(region.decay[i], first->decay[i]) &&
                   near(region.gamma[i], first->gamma[i]);
  }
  if (!separable_ || first == nullptr) {
    beta_.clear();
    return;
  }
  decay_ = first->decay;
  gamma_ = first->gamma;
  w_aa_ = first->w_aa;
  w_ac_ = first->w_ac;
  w_cc_ = first->w_cc;
}

void ViscoelasticCondensation::advance_contact_space(const Vector<double>& contact_forces,
                                                     const Vector<double>* contact_displacement) {
  const auto start = std::chrono::steady_clock::now();
  const unsigned int n = 3 * n_contacts();
  const std::size_t n_branches = beta_.size();
  // a^{n+1} = f^{n+1} - sum_i beta_i (e_i b_i^n - gamma_i a^n), u_c^{n+1} = C_eff a^{n+1}.
  for (unsigned int j = 0; j < n; ++j) {
    double a = contact_forces(j);
    for (std::size_t i = 0; i < n_branches; ++i)
      a -= beta_[i] * (decay_[i] * branch_force_state_[i](j) - gamma_[i] * force_state_(j));
    next_force_state_(j) = a;
  }
  if (contact_displacement)
    next_contact_displacement_ = *contact_displacement;
  else
    for (unsigned int r = 0; r < n; ++r) {
      const double* row = compliance_.data() + std::size_t{r} * n;
      double u = 0;
      for (unsigned int j = 0; j < n; ++j)
        u += row[j] * next_force_state_(j);
      next_contact_displacement_(r) = u;
    }
  // The step's dissipation, the quadrature form's integrated: q_i^T K_i q_i = beta_i b_i . q_c,i,
  // q_i^T K_i (u^{n+1} - u^n) = beta_i b_i . (u_c^{n+1} - u_c^n), and so on.
  for (std::size_t i = 0; i < n_branches; ++i) {
    const Vector<double>& b = branch_force_state_[i];
    const Vector<double>& q = branch_contact_history_[i];
    double aa = 0, ac = 0, cc = 0;
    for (unsigned int j = 0; j < n; ++j) {
      const double du = next_contact_displacement_(j) - contact_displacement_(j);
      aa += b(j) * q(j);
      ac += b(j) * du;
      cc += (next_force_state_(j) - force_state_(j)) * du;
    }
    dissipated_energy_ += beta_[i] * (w_aa_[i] * aa + w_ac_[i] * ac + w_cc_[i] * cc);
  }
  for (unsigned int j = 0; j < n; ++j) {
    const double da = next_force_state_(j) - force_state_(j);
    const double du = next_contact_displacement_(j) - contact_displacement_(j);
    external_work_ += 0.5 * (previous_forces_(j) + contact_forces(j)) * du;
    for (std::size_t i = 0; i < n_branches; ++i) {
      branch_force_state_[i](j) = decay_[i] * branch_force_state_[i](j) + gamma_[i] * da;
      branch_contact_history_[i](j) = decay_[i] * branch_contact_history_[i](j) + gamma_[i] * du;
    }
    force_state_(j) = next_force_state_(j);
    contact_displacement_(j) = next_contact_displacement_(j);
    previous_forces_(j) = contact_forces(j);
  }
  // d^{n+1} = -sum_i beta_i (e_i q_c,i^{n+1} - gamma_i u_c^{n+1}).
  for (unsigned int j = 0; j < n; ++j) {
    double d = 0;
    for (std::size_t i = 0; i < n_branches; ++i)
      d -= beta_[i] *
           (decay_[i] * branch_contact_history_[i](j) - gamma_[i] * contact_displacement_(j));
    history_displacement_(j) = d;
  }
  solution_current_ = false;
  time_ += parameters_.time_step;
  timings_.field_solve = 0;
  timings_.history = seconds_since(start);
}

void ViscoelasticCondensation::field_of_contact_forces(const Vector<double>& force,
                                                       Vector<double>& field) const {
  Vector<double> rhs(dof_handler_.n_dofs());
  for (unsigned int k = 0; k < n_contacts(); ++k)
    for (unsigned int d = 0; d < 3; ++d)
      rhs(contact_dofs_[k][d]) = force(3 * k + d);
  field.reinit(dof_handler_.n_dofs());
  impl_->solve(rhs.begin(), field.begin());
}

const Vector<double>& ViscoelasticCondensation::solution() const {
  if (!solution_current_) {
    field_of_contact_forces(force_state_, solution_);
    solution_current_ = true;
  }
  return solution_;
}

void ViscoelasticCondensation::reset() {
  for (auto* v : {&force_state_, &next_force_state_, &next_contact_displacement_})
    *v = 0;
  for (auto& v : branch_force_state_)
    v = 0;
  for (auto& v : branch_contact_history_)
    v = 0;
  solution_current_ = true;
  std::fill(history_.begin(), history_.end(), SymmetricTensor<2, 3>());
  std::fill(strain_.begin(), strain_.end(), SymmetricTensor<2, 3>());
  solution_ = 0;
  history_force_ = 0;
  history_solution_ = 0;
  history_displacement_ = 0;
  contact_displacement_ = 0;
  previous_forces_ = 0;
  std::fill(cell_dissipation_.begin(), cell_dissipation_.end(), 0.0);
  dissipated_energy_ = external_work_ = 0;
  time_ = 0;
}

double ViscoelasticCondensation::inverse_product(const SymmetricTensor<2, 3>& x,
                                                 const SymmetricTensor<2, 3>& y, double shear,
                                                 double bulk) {
  // C^-1 = P_vol / (3 K) + P_dev / (2 G): x : C^-1 : y = tr x tr y / (9 K) + dev x : dev y / (2 G).
  double product = 0;
  if (shear > 0)
    product += (deviator(x) * deviator(y)) / (2.0 * shear);
  if (bulk > 0)
    product += trace(x) * trace(y) / (9.0 * bulk);
  return product;
}

SymmetricTensor<2, 3> ViscoelasticCondensation::strain_at(unsigned int index, unsigned int q,
                                                          const double* local) const {
  const Impl& w = *impl_;
  const unsigned int n_q = discretization_.cell_quadrature.size();
  const std::size_t k = std::size_t{index} * n_q + q;
  Tensor<2, 3> grad_u;
  for (unsigned int j = 0; j < w.component.size(); ++j)
    grad_u[w.component[j]] +=
        local[j] * (w.reference_gradient[std::size_t{w.base[j]} * n_q + q] * w.inverse_jacobian[k]);
  return symmetrize(grad_u);
}

double ViscoelasticCondensation::stored_energy() const {
  if (contact_space_) {
    // C_inf = (1 - sum_i gamma_i beta_i) C_eff: 1/2 u^T K_inf u + sum_i 1/2 q_i^T K_i q_i.
    double long_term = 1;
    for (std::size_t i = 0; i < beta_.size(); ++i)
      long_term -= gamma_[i] * beta_[i];
    double energy = 0.5 * long_term * (force_state_ * contact_displacement_);
    for (std::size_t i = 0; i < beta_.size(); ++i)
      energy += 0.5 * beta_[i] * (branch_force_state_[i] * branch_contact_history_[i]);
    return energy;
  }
  Impl& w = *impl_;
  const unsigned int n_q = discretization_.cell_quadrature.size();
  double energy = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    const unsigned int index = cell->active_cell_index();
    const RegionStep& region = *cell_region_[index];
    w.gather(cell, solution_);
    const SymmetricTensor<2, 3>* h = history_.data() + cell_history_[index];
    for (unsigned int q = 0; q < n_q; ++q) {
      const SymmetricTensor<2, 3> eps = strain_at(index, q, w.local.data());
      double density = 0.5 * (eps * (region.long_term * eps));
      for (std::size_t i = 0; i < region.decay.size(); ++i, ++h)
        density += 0.5 * inverse_product(*h, *h, region.shear[i], region.bulk[i]);
      energy += density * w.jxw[std::size_t{index} * n_q + q];
    }
  }
  return energy;
}

ViscoelasticCellFields ViscoelasticCondensation::cell_fields() const {
  Impl& w = *impl_;
  const unsigned int n_q = discretization_.cell_quadrature.size();
  const unsigned int n_cells = triangulation_.n_active_cells();
  std::size_t n_branches = 0;
  for (const auto& [id, region] : regions_)
    n_branches = std::max(n_branches, region.decay.size());
  ViscoelasticCellFields fields;
  fields.von_mises.assign(n_cells, 0.0);
  fields.overstress.assign(n_branches, std::vector<double>(n_cells, 0.0));
  if (contact_space_) {
    // h_i = C_i : eps(q_i), q_i = K_eff^-1 P b_i.
    std::vector<Vector<double>> histories(n_branches);
    for (std::size_t i = 0; i < n_branches; ++i)
      field_of_contact_forces(branch_force_state_[i], histories[i]);
    const Vector<double>& u = solution();
    const SymmetricTensor<2, 3> identity = unit_symmetric_tensor<3>();
    std::vector<SymmetricTensor<2, 3>> overstress(std::size_t{n_q} * n_branches);
    for (const auto& cell : dof_handler_.active_cell_iterators()) {
      const unsigned int index = cell->active_cell_index();
      const RegionStep& region = *cell_region_[index];
      for (std::size_t i = 0; i < n_branches; ++i) {
        w.gather(cell, histories[i]);
        for (unsigned int q = 0; q < n_q; ++q) {
          const SymmetricTensor<2, 3> e = strain_at(index, q, w.local.data());
          overstress[i * n_q + q] =
              2.0 * region.shear[i] * deviator(e) + (region.bulk[i] * trace(e)) * identity;
        }
      }
      w.gather(cell, u);
      SymmetricTensor<2, 3> stress;
      double volume = 0;
      for (unsigned int q = 0; q < n_q; ++q) {
        const double jxw = w.jxw[std::size_t{index} * n_q + q];
        stress += (region.long_term * strain_at(index, q, w.local.data())) * jxw;
        for (std::size_t i = 0; i < n_branches; ++i) {
          stress += overstress[i * n_q + q] * jxw;
          fields.overstress[i][index] += overstress[i * n_q + q].norm() * jxw;
        }
        volume += jxw;
      }
      fields.von_mises[index] = von_mises(stress / volume);
      for (std::size_t i = 0; i < n_branches; ++i)
        fields.overstress[i][index] /= volume;
    }
    return fields;
  }
  fields.dissipated_energy_density.assign(n_cells, 0.0);
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    const unsigned int index = cell->active_cell_index();
    const RegionStep& region = *cell_region_[index];
    w.gather(cell, solution_);
    const SymmetricTensor<2, 3>* h = history_.data() + cell_history_[index];
    SymmetricTensor<2, 3> stress;
    double volume = 0;
    for (unsigned int q = 0; q < n_q; ++q) {
      const double jxw = w.jxw[std::size_t{index} * n_q + q];
      stress += (region.long_term * strain_at(index, q, w.local.data())) * jxw;
      for (std::size_t i = 0; i < region.decay.size(); ++i, ++h) {
        stress += *h * jxw;
        fields.overstress[i][index] += h->norm() * jxw;
      }
      volume += jxw;
    }
    fields.dissipated_energy_density[index] = cell_dissipation_[index] / volume;
    fields.von_mises[index] = von_mises(stress / volume);
    for (std::size_t i = 0; i < n_branches; ++i)
      fields.overstress[i][index] /= volume;
  }
  return fields;
}

SymmetricTensor<2, 3> ViscoelasticCondensation::mean_strain() const {
  FEValues<3> fe_values(*discretization_.mapping, *discretization_.fe,
                        discretization_.cell_quadrature, update_gradients | update_JxW_values);
  const FEValuesExtractors::Vector displacement(0);
  std::vector<SymmetricTensor<2, 3>> strains(discretization_.cell_quadrature.size());
  SymmetricTensor<2, 3> sum;
  double volume = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values[displacement].get_function_symmetric_gradients(solution(), strains);
    for (unsigned int q = 0; q < strains.size(); ++q) {
      sum += strains[q] * fe_values.JxW(q);
      volume += fe_values.JxW(q);
    }
  }
  return sum / volume;
}

} // namespace plantar::fem
