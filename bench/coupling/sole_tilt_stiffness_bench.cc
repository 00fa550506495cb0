// How stiffly a condensed sole holds its foot's tilt when only part of its face touches the
// ground, against the inverted pendulum's toppling stiffness m g z_c.
//
// The foot's rigid motion q = (t, theta) moves contact node k by R_k q, R_k = [I_3, -[x_k -
// x_0]_x] (x_0: the touching nodes' centroid). With the touching set A held by the ground
// (sticking) and the other nodes free, the forces are f_A = C_AA^-1 R_A q, so the foot's
// stiffness is K_A = R_A^T C_AA^-1 R_A (6 x 6). The tilt stiffness about x (roll) and y (pitch)
// with the rest of the wrench zero is k = 1 / [K_A^-1]_theta theta (N m/rad). A robot of mass m
// whose CoM is z_c above that support, standing on stiff, position-held joints, tilts with its
// foot: a moment M at the ground tilts it by M / k and moves its CoM by z_c M / k, which adds
// the gravity moment m g z_c M / k. For k < m g z_c a CoP moved by the ankle moves the CoM
// further the same way (the ankle strategy's sign reverses); above it, the ankle strategy keeps
// the fraction 1 - m g z_c / k of its effect. The set A: the nodes within a disc about the centre
// (all nodes: the flat ground) and three-node supports. A linear sole's K_A scales
// with E, so the 4 MPa column gives every E. Prints tables; never passes or fails.
// Usage: sole_tilt_stiffness_bench [supports.txt]
// With a file, the 3 cm P1 sole's stiffness on each line's support instead: "t F n x_1 y_1 ...
// x_n y_n" (s, N, the touching nodes' positions from the contact nodes' centroid, m; e.g. from a
// walk's sole series by bench/coupling/active_sets.py), each position taken to its nearest node.
#include "bench/coupling/sole_box_condensation.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

using namespace plantar;

namespace {

struct Support {
  double k_z = 0.0;     ///< N/m
  double k_roll = 0.0;  ///< N m/rad, about x
  double k_pitch = 0.0; ///< N m/rad, about y
  double x_range = 0.0; ///< m
  double y_range = 0.0; ///< m
};

/// The foot's stiffness on the contact nodes @p nodes of @p sole (sticking), see above.
Support support_stiffness(const coupling::CondensedSole& sole, const std::vector<int>& nodes) {
  const Eigen::MatrixX3d& x = sole.contact_positions();
  const Eigen::MatrixXd& c = sole.compliance();
  const int n = static_cast<int>(nodes.size());
  Eigen::Vector3d x0 = Eigen::Vector3d::Zero();
  for (const int k : nodes)
    x0 += x.row(k).transpose();
  x0 /= n;
  Eigen::MatrixXd c_aa(3 * n, 3 * n), r(3 * n, 6);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      c_aa.block<3, 3>(3 * i, 3 * j) = c.block<3, 3>(3 * nodes[i], 3 * nodes[j]);
    const Eigen::Vector3d d = x.row(nodes[i]).transpose() - x0;
    r.block<3, 3>(3 * i, 0).setIdentity();
    r.block<3, 3>(3 * i, 3) << 0.0, d.z(), -d.y(), -d.z(), 0.0, d.x(), d.y(), -d.x(), 0.0;
  }
  const Eigen::MatrixXd k_a = r.transpose() * c_aa.llt().solve(r);
  Support s;
  // Nodes on a line (or one node) leave a tilt free: k = 0 about it.
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(k_a);
  if (n >= 3 && lu.rank() == 6) {
    const Eigen::MatrixXd compliance = lu.inverse();
    s.k_z = 1.0 / compliance(2, 2);
    s.k_roll = 1.0 / compliance(3, 3);
    s.k_pitch = 1.0 / compliance(4, 4);
  }
  double x_min = 1e9, x_max = -1e9, y_min = 1e9, y_max = -1e9;
  for (const int k : nodes) {
    x_min = std::min(x_min, x(k, 0));
    x_max = std::max(x_max, x(k, 0));
    y_min = std::min(y_min, x(k, 1));
    y_max = std::max(y_max, x(k, 1));
  }
  s.x_range = x_max - x_min;
  s.y_range = y_max - y_min;
  return s;
}

/// The @p n contact nodes nearest (@p cx, @p cy) in the face's plane.
std::vector<int> nearest(const coupling::CondensedSole& sole, int n, double cx, double cy) {
  const Eigen::MatrixX3d& x = sole.contact_positions();
  std::vector<int> order(static_cast<std::size_t>(sole.n_contacts()));
  std::iota(order.begin(), order.end(), 0);
  auto d2 = [&](int k) {
    return (x(k, 0) - cx) * (x(k, 0) - cx) + (x(k, 1) - cy) * (x(k, 1) - cy);
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return d2(a) < d2(b); });
  order.resize(static_cast<std::size_t>(std::min(n, sole.n_contacts())));
  return order;
}

/// Three nodes nearest the vertices of a triangle of half-size @p a (m) around the centre:
/// (a, 0), (-a, a), (-a, -a).
std::vector<int> tripod(const coupling::CondensedSole& sole, double a) {
  std::vector<int> nodes;
  for (const auto& [px, py] : {std::pair{a, 0.0}, std::pair{-a, a}, std::pair{-a, -a}})
    nodes.push_back(nearest(sole, 1, px, py).front());
  return nodes;
}

void print_row(const std::string& label, int n, const Support& s, double toppling, double weight) {
  std::printf("%-26s %4d %5.1f x %4.1f %9.1f %9.0f %9.0f %7.2f %7.2f %8.2f\n", label.c_str(), n,
              100.0 * s.x_range, 100.0 * s.y_range, 1e-3 * s.k_z, s.k_roll, s.k_pitch,
              s.k_roll / toppling, s.k_pitch / toppling, 1e3 * weight / s.k_z);
}

/// The table of the supports in @p path (see above) on the walk's 3 cm P1 sole.
int supports_from_file(const char* path, double toppling) {
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "sole_tilt_stiffness_bench: cannot read %s\n", path);
    return 1;
  }
  const auto sole =
      bench::condense_sole_box(0.03, 64, coupling::CondensationParameters::Form::dense, false);
  std::printf("%7s %7s %4s %12s %9s %9s %7s %7s\n", "t (s)", "F (N)", "n", "extent (cm)", "k_roll",
              "k_pitch", "/mgz_c", "/mgz_c");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    double t = 0.0, force = 0.0;
    int n = 0;
    if (!(fields >> t >> force >> n))
      continue;
    std::vector<int> nodes;
    double x = 0.0, y = 0.0;
    while (fields >> x >> y)
      nodes.push_back(nearest(sole, 1, x, y).front());
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    const Support s = support_stiffness(sole, nodes);
    std::printf("%7.3f %7.0f %4zu %5.1f x %4.1f %9.0f %9.0f %7.2f %7.2f\n", t, force, nodes.size(),
                100.0 * s.x_range, 100.0 * s.y_range, s.k_roll, s.k_pitch, s.k_roll / toppling,
                s.k_pitch / toppling);
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  const double toppling = 58.0 * 9.81 * 0.815;
  const double weight = 58.0 * 9.81;
  if (argc > 1)
    return supports_from_file(argv[1], toppling);
  std::printf("Tilt stiffness of the HRP-2 sole box (0.2172 x 0.138 x 0.02 m, E = 4 MPa, nu = "
              "0.3; linear: multiply k by E / 4 MPa) on part of its face, sticking; m g z_c = "
              "%.0f N m/rad; compression under %.0f N\n",
              toppling, weight);
  for (const auto& [h, hex] :
       {std::pair{0.03, false}, std::pair{0.01, false}, std::pair{0.005, true}}) {
    const auto sole =
        bench::condense_sole_box(h, 64, coupling::CondensationParameters::Form::dense, hex);
    std::printf("\n%s, h = %.3f m, %d contact nodes\n", hex ? "Q1 hexahedra" : "P1 tetrahedra", h,
                sole.n_contacts());
    std::printf("%-26s %4s %12s %9s %9s %9s %7s %7s %8s\n", "support", "n", "extent (cm)",
                "k_z kN/m", "k_roll", "k_pitch", "/mgz_c", "/mgz_c", "dz (mm)");
    std::vector<int> all(static_cast<std::size_t>(sole.n_contacts()));
    std::iota(all.begin(), all.end(), 0);
    const Support face = support_stiffness(sole, all);
    print_row("whole face (flat ground)", sole.n_contacts(), face, toppling, weight);
    // The same from K_R of the condensation, computed through K_nn instead of C.
    const Eigen::Matrix<double, 6, 6> face_compliance = sole.rigid_motion_stiffness().inverse();
    std::printf("  check, CondensedSole::rigid_motion_stiffness(): k_roll, k_pitch relative "
                "differences %.1e, %.1e\n",
                std::abs(1.0 / face_compliance(3, 3) - face.k_roll) / face.k_roll,
                std::abs(1.0 / face_compliance(4, 4) - face.k_pitch) / face.k_pitch);
    // A laterally confined layer: k = E (1 - nu) / ((1 + nu)(1 - 2 nu)) I / t (an upper bound:
    // the sides bulge).
    const double e_oed = 4e6 * 0.7 / (1.3 * 0.4), length = 0.2172, width = 0.138, t = 0.02;
    std::printf("  closed form, confined layer E_oed I / t: k_roll %.0f, k_pitch %.0f N m/rad\n",
                e_oed * length * width * width * width / 12.0 / t,
                e_oed * width * length * length * length / 12.0 / t);
    for (const double radius : {0.06, 0.04, 0.03, 0.02}) {
      std::vector<int> disc;
      for (int k = 0; k < sole.n_contacts(); ++k) {
        const auto& x = sole.contact_positions();
        if (x(k, 0) * x(k, 0) + x(k, 1) * x(k, 1) <= radius * radius * (1.0 + 1e-9))
          disc.push_back(k);
      }
      if (disc.size() < 3)
        continue;
      print_row("disc r = " + std::to_string(static_cast<int>(100 * radius + 0.5)) + " cm",
                static_cast<int>(disc.size()), support_stiffness(sole, disc), toppling, weight);
    }
    for (const double a : {0.06, 0.04, 0.03, 0.02}) {
      const auto nodes = tripod(sole, a);
      print_row("tripod a = " + std::to_string(static_cast<int>(100 * a + 0.5)) + " cm", 3,
                support_stiffness(sole, nodes), toppling, weight);
    }
    std::fflush(stdout);
  }
  return 0;
}
