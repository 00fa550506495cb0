#include "fem/contact_condensation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {

using dealii::types::global_dof_index;

std::vector<std::array<global_dof_index, 3>>
boundary_nodes(const dealii::DoFHandler<3>& dof_handler, dealii::types::boundary_id boundary) {
  const auto& fe = dof_handler.get_fe();
  std::vector<global_dof_index> dofs;
  std::map<global_dof_index, std::array<global_dof_index, 3>> nodes;
  for (const auto& cell : dof_handler.active_cell_iterators())
    for (const unsigned int f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == boundary) {
        dofs.resize(fe.n_dofs_per_face(f));
        cell->face(f)->get_dof_indices(dofs);
        // Face dofs come node by node, components x, y, z within a node.
        for (unsigned int i = 0; i < dofs.size(); ++i)
          if (fe.face_system_to_component_index(i, f).first == 0) {
            for (unsigned int d = 1; d < 3; ++d)
              if (i + d >= dofs.size() || fe.face_system_to_component_index(i + d, f).first != d)
                throw std::logic_error("boundary_nodes: unexpected face dof ordering");
            nodes[dofs[i]] = {dofs[i], dofs[i + 1], dofs[i + 2]};
          }
      }
  std::vector<std::array<global_dof_index, 3>> result;
  result.reserve(nodes.size());
  for (const auto& [first, node] : nodes)
    result.push_back(node);
  return result;
}

void check_contact_nodes_free(const std::vector<std::array<global_dof_index, 3>>& nodes,
                              const dealii::AffineConstraints<double>& constraints,
                              const std::vector<dealii::Point<3>>& support_points,
                              dealii::types::boundary_id attached_boundary,
                              const std::string& who) {
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (const global_dof_index dof : nodes[k])
      if (constraints.is_constrained(dof)) {
        std::ostringstream msg;
        msg << who << ": contact node " << k << " at (" << support_points[dof]
            << ") m lies on the attached boundary " << attached_boundary
            << " (contact and attached faces must not touch)";
        throw std::invalid_argument(msg.str());
      }
}

void contact_block_of_inverse(const std::vector<unsigned int>& contact_index,
                              unsigned int n_unknowns, unsigned int block_size,
                              const BlockSolve& solve, double* compliance, const std::string& who) {
  const std::size_t n = contact_index.size();
  block_size = std::max(1u, std::min<unsigned int>(block_size, static_cast<unsigned int>(n)));
  std::vector<double> unit_vectors, solutions(std::size_t{n_unknowns} * block_size);
  for (std::size_t first = 0; first < n; first += block_size) {
    const auto count = static_cast<unsigned int>(std::min<std::size_t>(block_size, n - first));
    unit_vectors.assign(std::size_t{n_unknowns} * count, 0.0);
    for (unsigned int j = 0; j < count; ++j)
      unit_vectors[std::size_t{j} * n_unknowns + contact_index[first + j]] = 1.0;
    solve(unit_vectors.data(), solutions.data(), count);
    for (unsigned int j = 0; j < count; ++j) {
      const double* x = solutions.data() + std::size_t{j} * n_unknowns;
      double* column = compliance + (first + j) * n;
      for (std::size_t i = 0; i < n; ++i)
        column[i] = x[contact_index[i]];
    }
  }
  double largest = 0;
  for (std::size_t i = 0; i < n * n; ++i) {
    if (!std::isfinite(compliance[i]))
      throw std::runtime_error(who + ": the contact compliance C has non-finite entries");
    largest = std::max(largest, std::abs(compliance[i]));
  }
  if (n > 0 && !(largest > 0))
    throw std::runtime_error(who + ": the contact compliance C is zero");
}

double relative_asymmetry(const double* a, unsigned int n) {
  double asymmetry = 0, largest = 0;
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = 0; i < n; ++i) {
      largest = std::max(largest, std::abs(a[j * n + i]));
      if (i < j)
        asymmetry = std::max(asymmetry, std::abs(a[j * n + i] - a[i * n + j]));
    }
  return largest > 0 ? asymmetry / largest : 0.0;
}

void symmetrize(double* a, unsigned int n) {
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      a[i * n + j] = a[j * n + i] = 0.5 * (a[i * n + j] + a[j * n + i]);
}

} // namespace plantar::fem
