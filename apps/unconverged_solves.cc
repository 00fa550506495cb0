#include "apps/unconverged_solves.h"

#include "apps/contact_solver_name.h"
#include "fem/atomic_file.h"

#include <iomanip>

namespace plantar::app {

void UnconvergedSolves::write_csv(const std::filesystem::path& path) const {
  fem::write_file_atomically(path, [&](std::ostream& out) {
    out << "step,t,residual,n_contacts,iterations,status,finished_by,switch_reason,"
           "switch_iteration\n"
        << std::setprecision(17);
    for (const UnconvergedSolve& s : list_)
      out << s.step << "," << s.time << "," << s.residual << "," << s.n_contacts << ","
          << s.iterations << "," << contact::to_string(s.status) << ","
          << contact_solver_name(s.finished_by) << "," << contact::to_string(s.switch_reason) << ","
          << s.switch_iteration << "\n";
  });
}

} // namespace plantar::app
