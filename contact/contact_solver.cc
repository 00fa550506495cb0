#include "contact/contact_solver.h"

#include "contact/admm_solver.h"
#include "contact/auto_solver.h"
#include "contact/coulomb_cone.h"
#include "contact/gauss_seidel_solver.h"
#include "contact/semismooth_newton_solver.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace plantar::contact {

namespace {
// The iterative solvers, registered by their ContactSolverType (@p made: those of the earlier
// types): nullptr past the last type.
std::unique_ptr<IterativeSolver>
make_iterative_solver(ContactSolverType type,
                      const std::vector<std::unique_ptr<IterativeSolver>>& made) {
  switch (type) {
  case ContactSolverType::gauss_seidel:
    return std::make_unique<GaussSeidelSolver>();
  case ContactSolverType::admm:
    return std::make_unique<AdmmSolver>();
  case ContactSolverType::newton:
    return std::make_unique<SemismoothNewtonSolver>();
  case ContactSolverType::automatic: // runs the facade's Gauss-Seidel and Newton
    return std::make_unique<AutoSolver>(
        static_cast<GaussSeidelSolver&>(
            *made[static_cast<std::size_t>(ContactSolverType::gauss_seidel)]),
        static_cast<SemismoothNewtonSolver&>(
            *made[static_cast<std::size_t>(ContactSolverType::newton)]));
  }
  return nullptr;
}
} // namespace

ContactSolver::ContactSolver() {
  for (int type = 0;; ++type) {
    auto solver = make_iterative_solver(static_cast<ContactSolverType>(type), iterative_);
    if (solver == nullptr)
      break;
    iterative_.push_back(std::move(solver));
  }
  sized_.assign(iterative_.size(), true); // all sized for no contact
}

void ContactSolver::resize(int max_contacts, int rigid_rank) {
  resize(max_contacts, rigid_rank, ContactSolverType::gauss_seidel);
  for (std::size_t type = 0; type < iterative_.size(); ++type)
    if (!sized_[type]) {
      iterative_[type]->resize(max_contacts, rigid_rank);
      sized_[type] = true;
    }
}

bool ContactSolver::reserved(ContactSolverType type) const {
  const auto t = static_cast<std::size_t>(type);
  if (t >= iterative_.size() || !sized_[t])
    return false;
  // automatic runs Gauss-Seidel and Newton.
  return type != ContactSolverType::automatic ||
         (reserved(ContactSolverType::gauss_seidel) && reserved(ContactSolverType::newton));
}

void ContactSolver::resize(int max_contacts, int rigid_rank, ContactSolverType type) {
  if (max_contacts < 0 || rigid_rank < 0) {
    std::ostringstream msg;
    msg << "ContactSolver::resize: max_contacts = " << max_contacts
        << ", rigid_rank = " << rigid_rank << ", both must be >= 0";
    throw std::invalid_argument(msg.str());
  }
  max_contacts_ = max_contacts;
  rigid_rank_ = rigid_rank;
  products_.resize(max_contacts, rigid_rank);
  sticking_.resize(max_contacts, rigid_rank);
  rigid_sticking_.resize(max_contacts, rigid_rank);
  const auto needed = [type](ContactSolverType t) {
    return t == type || (type == ContactSolverType::automatic &&
                         (t == ContactSolverType::gauss_seidel || t == ContactSolverType::newton));
  };
  sized_.assign(iterative_.size(), false);
  for (std::size_t t = 0; t < iterative_.size(); ++t) {
    sized_[t] = needed(static_cast<ContactSolverType>(t));
    // The others' workspaces are released (sized for no contact).
    iterative_[t]->resize(sized_[t] ? max_contacts : 0, sized_[t] ? rigid_rank : 0);
  }
}

long ContactSolver::n_patch_factorizations() const {
  long n = 0;
  for (const auto& solver : iterative_)
    n += solver->n_patch_factorizations();
  return n;
}

double ContactSolver::complementarity_residual(const ContactProblem& problem,
                                               const Eigen::Ref<const Eigen::VectorXd>& p,
                                               const Eigen::Ref<const Eigen::VectorXd>& v) {
  double worst = 0.0;
  for (int k = 0; k < problem.n_contacts; ++k) {
    const double trace = problem.diagonal_block(k).trace();
    const double eta = trace > 0.0 ? 3.0 / trace : 1.0;
    const double r = contact_residual(p.segment<3>(3 * k), v.segment<3>(3 * k),
                                      problem.normal_bias[k], problem.friction[k], eta);
    if (!(r <= worst))
      worst = r;
  }
  return worst;
}

SolverResult ContactSolver::solve(const ContactProblem& problem, const SolverSettings& settings,
                                  Eigen::Ref<Eigen::VectorXd> impulses) {
  settings.validate();
  const auto type = static_cast<std::size_t>(settings.solver);
  if (type >= iterative_.size())
    throw std::invalid_argument("ContactSolver::solve: unknown SolverSettings::solver " +
                                std::to_string(type));
  if (!reserved(settings.solver))
    throw std::invalid_argument(std::string("ContactSolver::solve: solver ") +
                                to_string(settings.solver) +
                                " has no workspace: this ContactSolver was sized for another "
                                "type (resize(max_contacts, rigid_rank, type))");
  const int n = problem.n_contacts;
  if (n > max_contacts_ || problem.rigid_rank() != rigid_rank_ || impulses.size() < 3 * n) {
    std::ostringstream msg;
    msg << "ContactSolver::solve: problem has n_contacts = " << n << ", rigid rank "
        << problem.rigid_rank() << ", impulses size " << impulses.size()
        << "; workspace sized for max_contacts = " << max_contacts_ << ", rigid rank "
        << rigid_rank_ << " (call resize)";
    throw std::invalid_argument(msg.str());
  }
  problem.validate(/*check_matrices=*/false); // non-finite W shows as SolverStatus::non_finite
  bool compressed = false;
  for (const CompliantPatch& patch : problem.patches)
    compressed = compressed || patch.compressed != nullptr;
  if (compressed && settings.solver != ContactSolverType::gauss_seidel)
    throw std::invalid_argument(std::string("ContactSolver::solve: a compressed patch "
                                            "(CompliantPatch::compressed) needs the "
                                            "gauss-seidel solver, not ") +
                                to_string(settings.solver));
  SolverResult result;
  history_.size = 0;
  if (n == 0) {
    result.status = SolverStatus::converged;
    return result;
  }
  products_.prepare(problem);
  if (!settings.warm_start)
    impulses.head(3 * n).setZero();
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d p = impulses.segment<3>(3 * k);
    const Eigen::Vector3d projected =
        p.allFinite() ? project_onto_cone(p, problem.friction[k]) : Eigen::Vector3d::Zero();
    impulses.segment<3>(3 * k) = projected;
    // A caller's warm product is of the unprojected impulses: corrected by this change.
    products_.warm_change.segment<3>(3 * k) = projected - p;
    if (!p.allFinite())
      products_.warm_change.segment<3>(3 * k).setConstant(std::nan(""));
  }
  // The direct attempt, then the iteration (from the refused candidate and its products).
  DirectAttempt attempt = DirectAttempt::not_tried;
  StartProducts start = StartProducts::build;
  if (settings.sticking_direct && settings.warm_start && problem.general.empty() && !compressed) {
    bool rigid = true; // no contact on a compliant patch: W = G G^T
    for (const CompliantPatch& patch : problem.patches)
      rigid = rigid && patch.n_contacts == 0;
    result = rigid ? rigid_sticking_.solve(problem, settings, impulses, products_)
                   : sticking_.solve(problem, settings, impulses, products_);
    attempt = result.direct_attempt;
    if (attempt == DirectAttempt::accepted)
      return result;
    // StickingSolver's refused candidate is the start; RigidStickingSolver's is the warm start.
    if (!rigid &&
        (attempt == DirectAttempt::refused_cone || attempt == DirectAttempt::refused_residual))
      start = StartProducts::held;
  }
  result = iterative_[type]->solve(problem, settings, impulses, products_, start, history_);
  result.direct_attempt = attempt;
  if (settings.solver != ContactSolverType::automatic)
    result.finished_by = settings.solver;
  if (!impulses.head(3 * n).allFinite() || !std::isfinite(result.residual)) {
    result.status = SolverStatus::non_finite;
    impulses.head(3 * n).setZero();
  }
  return result;
}

} // namespace plantar::contact
