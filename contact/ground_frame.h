#pragma once
// The contact frame of the flat ground z = 0, the one convention for every contact of
// Plantar: rows (n, t1, t2) of a contact vector are the world's (z, x, y).
//   R_c = [n t1 t2] = [e_z e_x e_y]   (columns in world coordinates)
//   world = R_c c,   c = R_c^T world.

#include <Eigen/Core>

namespace plantar::contact {

/// R_c (3 x 3): contact components (n, t1, t2) -> world components.
inline Eigen::Matrix3d ground_frame() {
  Eigen::Matrix3d r;
  r << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  return r;
}

/// R_c^T (3 x 3): world components -> contact components (n, t1, t2).
inline Eigen::Matrix3d ground_frame_transpose() {
  Eigen::Matrix3d rt;
  rt << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  return rt;
}

/// R_c c: a contact-frame vector (n, t1, t2) in world components (x, y, z). Exact (a
/// permutation).
inline Eigen::Vector3d ground_to_world(const Eigen::Ref<const Eigen::Vector3d>& c) {
  return Eigen::Vector3d(c[1], c[2], c[0]);
}

/// R_c^T w: a world vector (x, y, z) in contact-frame components (n, t1, t2). Exact.
inline Eigen::Vector3d world_to_ground(const Eigen::Ref<const Eigen::Vector3d>& w) {
  return Eigen::Vector3d(w[2], w[0], w[1]);
}

} // namespace plantar::contact
