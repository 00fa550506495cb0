#include "fem/distributed_contact.h"

#include "fem/mesh_import.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/fe_values_extractors.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_precondition.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <petscksp.h>
#include <petscmat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace plantar::fem {

using namespace dealii;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The foot's rigid motion as a 3-component function (the initial guess u = rigid motion).
class RigidMotionFunction : public Function<3> {
public:
  explicit RigidMotionFunction(const RigidMotion& motion) : Function<3>(3), motion_(motion) {}
  double value(const Point<3>& x, const unsigned int component) const override {
    return motion_.displacement(x)[component];
  }

private:
  RigidMotion motion_;
};

void check_petsc(PetscErrorCode code, const char* what) {
  if (code != 0)
    throw std::runtime_error(std::string("static contact: PETSc error in ") + what);
}

} // namespace

Tensor<1, 3> RigidMotion::displacement(const Point<3>& x) const {
  return translation + cross_product_3d(rotation, x - center);
}

void DistributedContactSettings::validate() const {
  const auto fail = [](const std::string& name, double value, const std::string& range) {
    std::ostringstream msg;
    msg << "static contact: " << name << " = " << value << " is out of range: must be in " << range;
    throw std::invalid_argument(msg.str());
  };
  if (degree < 1 || degree > 2)
    fail("element degree", degree, "{1, 2}");
  if (refinements > 8)
    fail("refinements", refinements, "[0, 8]");
  if (!(friction >= 0 && friction <= 10))
    fail("friction coefficient", friction, "[0, 10]");
  if (!std::isfinite(ground_height))
    fail("ground height", ground_height, "finite values (m)");
  if (!(tolerance > 0 && tolerance <= 1e-2))
    fail("tolerance", tolerance, "(0, 1e-2]");
  if (max_iterations < 1 || max_iterations > 1000)
    fail("maximum iterations", max_iterations, "[1, 1000]");
  if (!(linear_tolerance > 0 && linear_tolerance < 1))
    fail("linear tolerance", linear_tolerance, "(0, 1)");
}

ContactLinearSolver parse_contact_linear_solver(const std::string& text,
                                                const std::string& parameter) {
  if (text == "mumps")
    return ContactLinearSolver::mumps;
  if (text == "gmres amg")
    return ContactLinearSolver::gmres_amg;
  if (text == "gmres gamg")
    return ContactLinearSolver::gmres_gamg;
  throw std::invalid_argument(parameter + " = '" + text + "': allowed mumps|gmres amg|gmres gamg");
}

DistributedContact::DistributedContact(MPI_Comm communicator, const Triangulation<3>& coarse,
                                       const MaterialTable& materials,
                                       const DistributedContactSettings& settings)
    : communicator_(communicator), materials_(materials), settings_(settings),
      triangulation_(communicator), fe_(FE_Q<3>(std::max(1u, settings.degree)), 3), mapping_(1),
      dof_handler_(triangulation_) {
  settings_.validate();
  if (coarse.n_active_cells() == 0)
    throw std::invalid_argument("static contact: the mesh holds no cell");
  if (cell_kind(coarse) != CellKind::hexahedron)
    throw std::invalid_argument(
        "static contact: the mesh holds tetrahedra; the distributed solve needs hexahedra "
        "(parallel::distributed::Triangulation refines hexahedra only): set Sole/Cell kind = "
        "hexahedron");
  const auto start = std::chrono::steady_clock::now();
  triangulation_.copy_triangulation(coarse);
  triangulation_.refine_global(settings_.refinements);
  setup();
  setup_time_ = seconds_since(start);
  const auto assembly_start = std::chrono::steady_clock::now();
  assemble();
  lumped_areas();
  if (settings_.linear_solver == ContactLinearSolver::gmres_gamg)
    gamg_setup(); // last: nothing throws after the solver is created
  assembly_time_ = seconds_since(assembly_start);
}

std::vector<DistributedContact::Node>
DistributedContact::owned_boundary_nodes(types::boundary_id boundary) const {
  std::map<types::global_dof_index, Node> nodes; // by x dof
  const auto& base = fe_.base_element(0);
  std::vector<types::global_dof_index> dofs(fe_.n_dofs_per_cell());
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (cell->is_artificial())
      continue;
    bool got_dofs = false;
    for (const unsigned int f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary() || cell->face(f)->boundary_id() != boundary)
        continue;
      if (!got_dofs) {
        cell->get_dof_indices(dofs);
        got_dofs = true;
      }
      for (unsigned int i = 0; i < fe_.n_dofs_per_cell(); ++i) {
        const auto [component, base_index] = fe_.system_to_component_index(i);
        if (component != 0 || !fe_.has_support_on_face(i, f) || !owned_dofs_.is_element(dofs[i]) ||
            nodes.count(dofs[i]) != 0)
          continue;
        Node node;
        for (unsigned int d = 0; d < 3; ++d)
          node.dofs[d] = dofs[fe_.component_to_system_index(d, base_index)];
        node.position =
            mapping_.transform_unit_to_real_cell(cell, base.unit_support_point(base_index));
        nodes.emplace(dofs[i], node);
      }
    }
  }
  std::vector<Node> result;
  result.reserve(nodes.size());
  for (const auto& [dof, node] : nodes)
    result.push_back(node);
  return result;
}

void DistributedContact::setup() {
  dof_handler_.distribute_dofs(fe_);
  owned_dofs_ = dof_handler_.locally_owned_dofs();
  DoFTools::extract_locally_relevant_dofs(dof_handler_, relevant_dofs_);
  DynamicSparsityPattern dsp(relevant_dofs_);
  DoFTools::make_sparsity_pattern(dof_handler_, dsp);
  SparsityTools::distribute_sparsity_pattern(dsp, owned_dofs_, communicator_, relevant_dofs_);
  stiffness_.reinit(owned_dofs_, owned_dofs_, dsp, communicator_);
  system_.reinit(owned_dofs_, owned_dofs_, dsp, communicator_);
  // The Dirichlet rows (MatZeroRows) keep their pattern, so that K can be copied in again.
  check_petsc(MatSetOption(system_, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE), "MatSetOption");
  for (auto* vector : {&solution_, &forces_, &rhs_, &constrained_values_})
    vector->reinit(owned_dofs_, communicator_);
  if (settings_.linear_solver != ContactLinearSolver::mumps)
    for (auto* vector : {&increment_, &newton_residual_})
      vector->reinit(owned_dofs_, communicator_);
  ghosted_solution_.reinit(owned_dofs_, relevant_dofs_, communicator_);
  ghosted_traction_.reinit(owned_dofs_, relevant_dofs_, communicator_);

  contact_nodes_ = owned_boundary_nodes(settings_.contact_boundary);
  top_nodes_ = owned_boundary_nodes(settings_.attached_boundary);
  n_contact_nodes_ =
      Utilities::MPI::sum(static_cast<unsigned int>(contact_nodes_.size()), communicator_);
  const unsigned int n_top =
      Utilities::MPI::sum(static_cast<unsigned int>(top_nodes_.size()), communicator_);
  if (n_contact_nodes_ == 0 || n_top == 0)
    throw std::invalid_argument(
        "static contact: boundary id " +
        std::to_string(n_top == 0 ? settings_.attached_boundary : settings_.contact_boundary) +
        " (" + (n_top == 0 ? "attached top" : "contact bottom") + ") holds no face");
  // A node on both faces would be attached and in contact at once.
  std::vector<types::global_dof_index> top_x;
  for (const auto& node : top_nodes_)
    top_x.push_back(node.dofs[0]);
  for (const auto& node : contact_nodes_)
    if (std::binary_search(top_x.begin(), top_x.end(), node.dofs[0])) {
      std::ostringstream msg;
      msg << "static contact: contact node at (" << node.position
          << ") m lies on the attached boundary " << settings_.attached_boundary;
      throw std::invalid_argument(msg.str());
    }
  states_.assign(contact_nodes_.size(), NodeState::separated);
  xi_.assign(contact_nodes_.size(), {});
}

void DistributedContact::assemble() {
  const QGauss<3> quadrature(settings_.degree + 1);
  FEValues<3> fe_values(mapping_, fe_, quadrature, update_gradients | update_JxW_values);
  const unsigned int n_dofs_cell = fe_.n_dofs_per_cell();
  FullMatrix<double> cell_matrix(n_dofs_cell, n_dofs_cell);
  std::vector<types::global_dof_index> dofs(n_dofs_cell);
  std::vector<SymmetricTensor<2, 3>> eps_phi(n_dofs_cell);
  const FEValuesExtractors::Vector displacement(0);
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned())
      continue;
    fe_values.reinit(cell);
    cell_matrix = 0;
    const SymmetricTensor<4, 3>& C = materials_[cell->material_id()].stiffness();
    for (unsigned int q = 0; q < quadrature.size(); ++q) {
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
    cell->get_dof_indices(dofs);
    stiffness_.add(dofs, cell_matrix);
  }
  stiffness_.compress(VectorOperation::add);

  // c: the mean diagonal of K on the contact dofs (N/m), scale of the complementarity functions.
  double sum = 0;
  for (const auto& node : contact_nodes_)
    for (unsigned int d = 0; d < 3; ++d)
      sum += stiffness_.diag_element(node.dofs[d]);
  complementarity_scale_ = Utilities::MPI::sum(sum, communicator_) / (3.0 * n_contact_nodes_);
}

void DistributedContact::lumped_areas() {
  const QGauss<2> quadrature(settings_.degree + 1);
  FEFaceValues<3> fe_face(mapping_, fe_, quadrature, update_values | update_JxW_values);
  std::vector<types::global_dof_index> dofs(fe_.n_dofs_per_cell());
  PETScWrappers::MPI::Vector areas(owned_dofs_, communicator_);
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned())
      continue;
    for (const unsigned int f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary() ||
          cell->face(f)->boundary_id() != settings_.contact_boundary)
        continue;
      fe_face.reinit(cell, f);
      cell->get_dof_indices(dofs);
      for (unsigned int i = 0; i < fe_.n_dofs_per_cell(); ++i) {
        if (fe_.system_to_component_index(i).first != 2 || !fe_.has_support_on_face(i, f))
          continue;
        double integral = 0;
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          integral += fe_face.shape_value(i, q) * fe_face.JxW(q);
        areas(dofs[i]) += integral;
      }
    }
  }
  areas.compress(VectorOperation::add);
  contact_areas_.resize(contact_nodes_.size());
  for (std::size_t k = 0; k < contact_nodes_.size(); ++k)
    contact_areas_[k] = areas(contact_nodes_[k].dofs[2]);
}

double DistributedContact::evaluate() {
  stiffness_.vmult(forces_, solution_);
  const double c = complementarity_scale_, mu = settings_.friction;
  double residual = 0, max_force = 0;
  for (std::size_t k = 0; k < contact_nodes_.size(); ++k) {
    const Node& node = contact_nodes_[k];
    Tensor<1, 3> lambda, u;
    for (unsigned int d = 0; d < 3; ++d) {
      lambda[d] = forces_(node.dofs[d]);
      u[d] = solution_(node.dofs[d]);
    }
    const double gap = node.position[2] + u[2] - settings_.ground_height;
    const double xi_n = lambda[2] - c * gap;
    const double xi_x = lambda[0] - c * u[0], xi_y = lambda[1] - c * u[1];
    const double xi_n_plus = std::max(0.0, xi_n);
    const double xi_t_norm = std::hypot(xi_x, xi_y);
    const double radius = mu * xi_n_plus;
    const double scale = xi_t_norm > radius ? radius / xi_t_norm : 1.0;
    const double c_n = lambda[2] - xi_n_plus;
    const double p_x = lambda[0] - scale * xi_x, p_y = lambda[1] - scale * xi_y;
    residual = std::max(residual, std::sqrt(c_n * c_n + p_x * p_x + p_y * p_y));
    max_force = std::max(max_force, lambda.norm());
    states_[k] = xi_n <= 0            ? NodeState::separated
                 : xi_t_norm < radius ? NodeState::stick
                                      : NodeState::slip;
    xi_[k] = {xi_n, xi_x, xi_y, lambda[0], lambda[1], lambda[2]};
  }
  residual = Utilities::MPI::max(residual, communicator_);
  // The reference force: the largest nodal force, at least c x 1 nm (no contact at all).
  max_force = std::max(Utilities::MPI::max(max_force, communicator_), c * 1e-9);
  return residual / max_force;
}

void DistributedContact::build_system(const RigidMotion& foot) {
  const double c = complementarity_scale_, mu = settings_.friction;
  const Mat stiffness = stiffness_, system = system_;
  check_petsc(MatCopy(stiffness, system, SAME_NONZERO_PATTERN), "MatCopy");
  rhs_ = 0;
  constrained_values_ = 0;
  std::vector<PetscInt> rows;
  const auto constrain = [&](types::global_dof_index dof, double value) {
    rows.push_back(static_cast<PetscInt>(dof));
    constrained_values_(dof) = value;
  };
  for (const Node& node : top_nodes_) {
    const Tensor<1, 3> u = foot.displacement(node.position);
    for (unsigned int d = 0; d < 3; ++d)
      constrain(node.dofs[d], u[d]);
  }
  std::array<std::vector<PetscInt>, 3> columns;
  std::array<std::vector<PetscScalar>, 3> values;
  std::vector<PetscScalar> row_values;
  for (std::size_t k = 0; k < contact_nodes_.size(); ++k) {
    const Node& node = contact_nodes_[k];
    if (states_[k] == NodeState::separated)
      continue; // lambda = 0: the rows of K, right-hand side 0
    constrain(node.dofs[2], settings_.ground_height - node.position[2]); // g = 0
    if (states_[k] == NodeState::stick) {
      constrain(node.dofs[0], 0.0); // s = 0
      constrain(node.dofs[1], 0.0);
      continue;
    }
    if (mu == 0)
      continue; // frictionless slip: lambda_t = 0, the rows of K
    // Slip: the linearised C_t = 0 divided by a = |xi_t| (HSW 2008, with lambda_t projected
    // onto the cone in the Jacobian):
    //   M1 lambda_t' + M2 s' - mu n lambda_n' = lt - m n,
    //   M1 = (1 - m/a) I + lt n^T / a,  M2 = -c (lt n^T / a - (m/a) I),
    // n = xi_t / a, m = mu xi_n, lt = lambda_t min(1, m / |lambda_t|), lambda' = K_node u'.
    const auto& xi = xi_[k];
    const double a = std::hypot(xi[1], xi[2]), m = mu * xi[0];
    const double n[2] = {xi[1] / a, xi[2] / a};
    const double lambda_t = std::hypot(xi[3], xi[4]);
    const double cone = lambda_t > m ? m / lambda_t : 1.0;
    const double lt[2] = {xi[3] * cone, xi[4] * cone};
    for (unsigned int d = 0; d < 3; ++d) {
      PetscInt n_columns = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* vals = nullptr;
      const PetscInt row = static_cast<PetscInt>(node.dofs[d]);
      check_petsc(MatGetRow(stiffness, row, &n_columns, &cols, &vals), "MatGetRow");
      columns[d].assign(cols, cols + n_columns);
      values[d].assign(vals, vals + n_columns);
      check_petsc(MatRestoreRow(stiffness, row, &n_columns, &cols, &vals), "MatRestoreRow");
    }
    if (columns[1] != columns[0] || columns[2] != columns[0])
      throw std::logic_error("static contact: the rows of a contact node differ in pattern");
    for (unsigned int i = 0; i < 2; ++i) {
      row_values.assign(columns[0].size(), 0.0);
      for (std::size_t e = 0; e < columns[0].size(); ++e) {
        double v = -mu * n[i] * values[2][e];
        for (unsigned int j = 0; j < 2; ++j)
          v += ((i == j ? 1.0 - m / a : 0.0) + lt[i] * n[j] / a) * values[j][e];
        for (unsigned int j = 0; j < 2; ++j)
          if (columns[0][e] == static_cast<PetscInt>(node.dofs[j]))
            v += -c * (lt[i] * n[j] / a - (i == j ? m / a : 0.0));
        row_values[e] = v;
      }
      const PetscInt row = static_cast<PetscInt>(node.dofs[i]);
      check_petsc(MatSetValues(system, 1, &row, static_cast<PetscInt>(columns[0].size()),
                               columns[0].data(), row_values.data(), INSERT_VALUES),
                  "MatSetValues");
      rhs_(node.dofs[i]) = lt[i] - m * n[i];
    }
  }
  check_petsc(MatAssemblyBegin(system, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  check_petsc(MatAssemblyEnd(system, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  rhs_.compress(VectorOperation::insert);
  constrained_values_.compress(VectorOperation::insert);
  const Vec x = constrained_values_, b = rhs_;
  check_petsc(MatZeroRows(system, static_cast<PetscInt>(rows.size()), rows.data(), c, x, b),
              "MatZeroRows");
}

void DistributedContact::gamg_setup() {
  // GAMG aggregates nodes (3 x 3 blocks) and needs each node's x, y, z dofs consecutive, and
  // their coordinates for the rigid-body modes.
  const types::global_dof_index first = owned_dofs_.nth_index_in_set(0);
  const std::size_t n_owned = owned_dofs_.n_elements();
  if (n_owned % 3 != 0 || first % 3 != 0)
    throw std::logic_error("static contact: owned dofs not in whole nodes");
  std::vector<double> coordinates(n_owned, std::numeric_limits<double>::quiet_NaN());
  const Quadrature<3> support(fe_.base_element(0).get_unit_support_points());
  FEValues<3> fe_values(mapping_, fe_, support, update_quadrature_points);
  std::vector<types::global_dof_index> dofs(fe_.n_dofs_per_cell());
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned())
      continue;
    fe_values.reinit(cell);
    cell->get_dof_indices(dofs);
    for (unsigned int i = 0; i < dofs.size(); ++i) {
      if (!owned_dofs_.is_element(dofs[i]))
        continue;
      const auto [component, base_index] = fe_.system_to_component_index(i);
      const std::size_t local = dofs[i] - first;
      if (local % 3 != component)
        throw std::logic_error("static contact: a node's dofs are not x, y, z consecutive");
      coordinates[local] = fe_values.quadrature_point(base_index)[component];
    }
  }
  for (const double x : coordinates)
    if (!std::isfinite(x))
      throw std::logic_error("static contact: an owned dof lies on no owned cell");
  // The six rigid-body modes, attached to the Newton matrix (kept by MatCopy of K into it).
  const Mat matrix = system_;
  check_petsc(MatSetBlockSize(matrix, 3), "MatSetBlockSize");
  Vec coordinate_vector = nullptr;
  MatNullSpace rigid_modes = nullptr;
  check_petsc(VecCreateMPI(communicator_, static_cast<PetscInt>(n_owned), PETSC_DETERMINE,
                           &coordinate_vector),
              "VecCreateMPI");
  check_petsc(VecSetBlockSize(coordinate_vector, 3), "VecSetBlockSize");
  PetscScalar* x = nullptr;
  check_petsc(VecGetArray(coordinate_vector, &x), "VecGetArray");
  std::copy(coordinates.begin(), coordinates.end(), x);
  check_petsc(VecRestoreArray(coordinate_vector, &x), "VecRestoreArray");
  const PetscErrorCode code = MatNullSpaceCreateRigidBody(coordinate_vector, &rigid_modes);
  VecDestroy(&coordinate_vector);
  check_petsc(code, "MatNullSpaceCreateRigidBody");
  const PetscErrorCode set = MatSetNearNullSpace(matrix, rigid_modes);
  MatNullSpaceDestroy(&rigid_modes);
  check_petsc(set, "MatSetNearNullSpace");
  // GMRES(200) + GAMG, kept over the Newton iterations and solves: the aggregates and
  // prolongators of the first system are reused (the systems differ in the contact rows only),
  // the Galerkin products recomputed. PETSc options with the prefix contact_ (e.g.
  // -contact_pc_gamg_threshold 0.02) adjust it.
  check_petsc(KSPCreate(communicator_, &ksp_), "KSPCreate");
  check_petsc(KSPSetOptionsPrefix(ksp_, "contact_"), "KSPSetOptionsPrefix");
  check_petsc(KSPSetType(ksp_, KSPGMRES), "KSPSetType");
  check_petsc(KSPGMRESSetRestart(ksp_, 200), "KSPGMRESSetRestart");
  check_petsc(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  check_petsc(KSPSetPCSide(ksp_, PC_RIGHT), "KSPSetPCSide");
  check_petsc(
      KSPSetTolerances(ksp_, settings_.linear_tolerance, PETSC_DEFAULT, PETSC_DEFAULT, 5000),
      "KSPSetTolerances");
  PC pc = nullptr;
  check_petsc(KSPGetPC(ksp_, &pc), "KSPGetPC");
  check_petsc(PCSetType(pc, PCGAMG), "PCSetType");
  check_petsc(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE), "PCGAMGSetReuseInterpolation");
  check_petsc(KSPSetFromOptions(ksp_), "KSPSetFromOptions");
}

DistributedContact::~DistributedContact() {
  if (ksp_ != nullptr)
    KSPDestroy(&ksp_);
}

void DistributedContact::linear_solve() {
  if (settings_.linear_solver == ContactLinearSolver::mumps) {
    SolverControl control(1, 0);
    PETScWrappers::SparseDirectMUMPS mumps(control, communicator_);
    mumps.solve(system_, solution_, rhs_);
    return;
  }
  iterative_solve();
}

void DistributedContact::iterative_solve() {
  // The Newton system's residual b - A u (on the Dirichlet rows c (value - u)).
  system_.vmult(newton_residual_, solution_);
  newton_residual_.sadd(-1.0, 1.0, rhs_);
  increment_ = 0;
  const double tolerance = settings_.linear_tolerance * newton_residual_.l2_norm();
  const char* name =
      settings_.linear_solver == ContactLinearSolver::gmres_amg ? "BoomerAMG" : "GAMG";
  const auto fail = [&](PetscInt iterations, double residual) {
    std::ostringstream msg;
    msg << "static contact: GMRES + " << name << " did not converge: " << iterations
        << " iterations, residual " << residual << " > " << tolerance;
    throw std::runtime_error(msg.str());
  };
  if (settings_.linear_solver == ContactLinearSolver::gmres_amg) {
    SolverControl control(5000, tolerance);
    PETScWrappers::SolverGMRES gmres(control, communicator_,
                                     PETScWrappers::SolverGMRES::AdditionalData(200));
    PETScWrappers::PreconditionBoomerAMG::AdditionalData data;
    data.symmetric_operator = false;
    data.strong_threshold = 0.5;
    PETScWrappers::PreconditionBoomerAMG amg(system_, data);
    try {
      gmres.solve(system_, increment_, newton_residual_, amg);
    } catch (const std::exception&) {
      fail(control.last_step(), control.last_value());
    }
    report_.linear_iterations += control.last_step();
  } else {
    const Mat matrix = system_;
    const Vec b = newton_residual_, du = increment_;
    check_petsc(KSPSetOperators(ksp_, matrix, matrix), "KSPSetOperators");
    check_petsc(KSPSolve(ksp_, b, du), "KSPSolve");
    KSPConvergedReason reason;
    PetscInt iterations = 0;
    PetscReal residual = 0;
    check_petsc(KSPGetConvergedReason(ksp_, &reason), "KSPGetConvergedReason");
    check_petsc(KSPGetIterationNumber(ksp_, &iterations), "KSPGetIterationNumber");
    check_petsc(KSPGetResidualNorm(ksp_, &residual), "KSPGetResidualNorm");
    if (reason < 0)
      fail(iterations, residual);
    report_.linear_iterations += iterations;
  }
  solution_ += increment_;
}

const ContactSolveReport& DistributedContact::solve(const RigidMotion& foot) {
  const auto start = std::chrono::steady_clock::now();
  report_ = ContactSolveReport();
  const RigidMotionFunction rigid(foot);
  VectorTools::interpolate(mapping_, dof_handler_, rigid, solution_);
  double residual = evaluate();
  while (residual > settings_.tolerance) {
    if (report_.iterations == settings_.max_iterations) {
      std::ostringstream msg;
      msg << "static contact: the semismooth Newton method did not converge after "
          << report_.iterations << " iterations: complementarity residual " << residual
          << " > tolerance " << settings_.tolerance
          << " (relative to the largest nodal force); raise the maximum iterations or check "
             "the foot motion";
      throw std::runtime_error(msg.str());
    }
    const auto iteration_start = std::chrono::steady_clock::now();
    build_system(foot);
    linear_solve();
    ++report_.iterations;
    residual = evaluate();
    report_.iteration_times.push_back(seconds_since(iteration_start));
  }
  report_.residual = residual;
  unsigned int counts[3] = {0, 0, 0};
  for (const NodeState state : states_)
    ++counts[static_cast<int>(state)];
  report_.n_separated = Utilities::MPI::sum(counts[0], communicator_);
  report_.n_stick = Utilities::MPI::sum(counts[1], communicator_);
  report_.n_slip = Utilities::MPI::sum(counts[2], communicator_);

  ghosted_solution_ = solution_;
  PETScWrappers::MPI::Vector traction(owned_dofs_, communicator_);
  for (std::size_t k = 0; k < contact_nodes_.size(); ++k)
    for (unsigned int d = 0; d < 3; ++d)
      traction(contact_nodes_[k].dofs[d]) = xi_[k][3 + d] / contact_areas_[k];
  traction.compress(VectorOperation::insert);
  ghosted_traction_ = traction;
  report_.solve_time = seconds_since(start);
  return report_;
}

std::vector<ContactNode> DistributedContact::gather_contact_nodes() const {
  std::vector<double> local;
  constexpr std::size_t n_values = 11;
  local.reserve(n_values * contact_nodes_.size());
  for (std::size_t k = 0; k < contact_nodes_.size(); ++k) {
    for (unsigned int d = 0; d < 3; ++d)
      local.push_back(contact_nodes_[k].position[d]);
    for (unsigned int d = 0; d < 3; ++d)
      local.push_back(xi_[k][3 + d]);
    for (unsigned int d = 0; d < 3; ++d)
      local.push_back(solution_(contact_nodes_[k].dofs[d]));
    local.push_back(contact_areas_[k]);
    local.push_back(static_cast<double>(states_[k]));
  }
  std::vector<ContactNode> nodes;
  for (const auto& part : Utilities::MPI::all_gather(communicator_, local))
    for (std::size_t i = 0; i + n_values <= part.size(); i += n_values) {
      ContactNode node;
      for (unsigned int d = 0; d < 3; ++d) {
        node.position[d] = part[i + d];
        node.force[d] = part[i + 3 + d];
        node.displacement[d] = part[i + 6 + d];
      }
      node.area = part[i + 9];
      node.state = static_cast<NodeState>(static_cast<int>(part[i + 10]));
      nodes.push_back(node);
    }
  const auto key = [](const Point<3>& p) {
    return std::make_tuple(std::llround(p[0] * 1e9), std::llround(p[1] * 1e9),
                           std::llround(p[2] * 1e9));
  };
  std::sort(nodes.begin(), nodes.end(), [&](const ContactNode& a, const ContactNode& b) {
    return key(a.position) < key(b.position);
  });
  return nodes;
}

Tensor<1, 3> DistributedContact::foot_force() const {
  Tensor<1, 3> sum;
  for (const Node& node : top_nodes_)
    for (unsigned int d = 0; d < 3; ++d)
      sum[d] += forces_(node.dofs[d]);
  return Utilities::MPI::sum(sum, communicator_);
}

Tensor<1, 3> DistributedContact::foot_moment(const Point<3>& point) const {
  Tensor<1, 3> sum;
  for (const Node& node : top_nodes_) {
    Tensor<1, 3> force;
    for (unsigned int d = 0; d < 3; ++d)
      force[d] = forces_(node.dofs[d]);
    sum += cross_product_3d(node.position - point, force);
  }
  return Utilities::MPI::sum(sum, communicator_);
}

Tensor<1, 3> DistributedContact::ground_force() const {
  Tensor<1, 3> sum;
  for (const auto& xi : xi_)
    for (unsigned int d = 0; d < 3; ++d)
      sum[d] += xi[3 + d];
  return Utilities::MPI::sum(sum, communicator_);
}

double DistributedContact::max_pressure() const {
  double pressure = 0;
  for (std::size_t k = 0; k < xi_.size(); ++k)
    pressure = std::max(pressure, xi_[k][5] / contact_areas_[k]);
  return Utilities::MPI::max(pressure, communicator_);
}

} // namespace plantar::fem
