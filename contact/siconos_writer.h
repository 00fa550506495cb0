#pragma once
// A contact problem written as Siconos numerics' FrictionContactProblem text (its
// frictionContact_printInFile layout, dense storage): u = W r + q, r in the Coulomb cones,
// u + mu ||u_T|| e_N in their duals. Plantar's v = W p + v_free with v_n + b >= 0 is that
// problem with r = p and q = v_free + b e_N (the normal bias moved into q). For replaying a
// solve that failed, with any solver (bench/contact/fc3d_bench reads it).

#include "contact/contact_problem.h"

#include <ostream>

namespace plantar::contact {

/// Writes the leading n_contacts of @p problem: "3", n, then W (storage 0, 3n 3n, 3n 3n, its
/// 9 n^2 entries column-major), q (3n) and mu (n), one number per line, 17 significant
/// digits. W is assembled densely (allocates: for diagnostics, not in the time loop).
void write_siconos_problem(const ContactProblem& problem, std::ostream& out);

/// Writes a start for that problem's solve, @p impulses (N s, 3 n_contacts, ordered as W's rows):
/// "3", n_contacts, then the 3 n_contacts impulses, one number per line, 17 significant digits
/// (read by tests/contact/siconos_format.h read_warm_start).
void write_warm_start(int n_contacts, const Eigen::Ref<const Eigen::VectorXd>& impulses,
                      std::ostream& out);

} // namespace plantar::contact
