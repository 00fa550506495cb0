#include "contact/siconos_writer.h"

#include <Eigen/Core>

namespace plantar::contact {

void write_siconos_problem(const ContactProblem& problem, std::ostream& out) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  Eigen::MatrixXd w;
  problem.assemble_delassus(w);
  const std::streamsize precision = out.precision(17);
  out << 3 << "\n"
      << n << "\n"
      << 0 << "\n"
      << n3 << "\n"
      << n3 << "\n"
      << n3 << "\n"
      << n3 << "\n";
  for (int j = 0; j < n3; ++j)
    for (int i = 0; i < n3; ++i)
      out << w(i, j) << "\n";
  for (int i = 0; i < n3; ++i)
    out << problem.free_velocity[i] + (i % 3 == 0 ? problem.normal_bias[i / 3] : 0.0) << "\n";
  for (int k = 0; k < n; ++k)
    out << problem.friction[k] << "\n";
  out.precision(precision);
}

void write_warm_start(int n_contacts, const Eigen::Ref<const Eigen::VectorXd>& impulses,
                      std::ostream& out) {
  const std::streamsize precision = out.precision(17);
  out << 3 << "\n" << n_contacts << "\n";
  for (int i = 0; i < 3 * n_contacts; ++i)
    out << impulses[i] << "\n";
  out.precision(precision);
}

} // namespace plantar::contact
