// Reduced soles built from the factorization of K (no dense C) against those built from the
// dense C, for decreasing mesh size h: set-up time and memory of each route, the reduction
// error estimate against the number of patches for uniform and Chebyshev-graded grids, and
// the difference of the two routes' C_r; the graded grids also with a patch's force shared by
// the nodes' areas (coupling::pressure_weights: a uniform patch pressure), "chebyshev-area",
// and in the bilinear basis (one patch per grid vertex, area weights), "chebyshev-bilinear".
// Where the dense route runs, also the pressure field's error under rigid motions of the bonded
// face (all nodes stuck): the relative area-weighted L2 error of the nodal normal force per area,
// f_r = A C_r^-1 R_r a against f = C^-1 R a, for a = z translation, pitch and roll. The HRP-2
// sole of meshes/sole_box.geo (Q1, E = 4 MPa, nu = 0.3). A timing app, not a test: prints
// tables, never passes or fails.
// Usage: reduction_bench [--dense-up-to H] [h1 h2 ...] (m); the dense route is run for
// h >= H only (default 0.004: below, C no longer fits a 2-core, 24 GB machine's time budget).
#include "bench/coupling/sole_box_condensation.h"
#include "bench/fem/peak_memory.h"
#include "coupling/reduced_sole.h"

#include <Eigen/Cholesky>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace plantar;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

const char* name(coupling::GridSpacing spacing) {
  return spacing == coupling::GridSpacing::uniform ? "uniform" : "chebyshev";
}

} // namespace

int main(int argc, char** argv) {
  double dense_up_to = 0.004;
  std::vector<double> sizes;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--dense-up-to" && i + 1 < argc)
      dense_up_to = std::atof(argv[++i]);
    else
      sizes.push_back(std::atof(arg.c_str()));
  }
  if (sizes.empty())
    sizes = {0.02, 0.01, 0.005};
  using Form = coupling::CondensationParameters::Form;
  std::printf("# set-up: route, h (m), contact nodes, set-up s (assembly + factorization + "
              "solves), kept MB, peak RSS MB so far\n");
  std::printf("# grids: h, spacing, g, patches, estimate, C_r s (3P solves), max |C_r(K) - "
              "C_r(C)| / max |C_r(C)|, pressure error z, pitch, roll (dense route only)\n");
  for (const double h : sizes) {
    auto start = std::chrono::steady_clock::now();
    const coupling::CondensedSole factored = bench::condense_sole_box(h, 64, Form::factorization);
    const double t_factored = seconds_since(start);
    const int n = factored.n_contacts();
    std::printf("setup factorization %.4f %d %.3f %.2f %.1f\n", h, n, t_factored,
                factored.memory().total() / 1e6, bench::peak_megabytes());
    std::fflush(stdout);
    const bool with_dense = h >= dense_up_to;
    std::unique_ptr<coupling::CondensedSole> dense;
    if (with_dense) {
      start = std::chrono::steady_clock::now();
      dense =
          std::make_unique<coupling::CondensedSole>(bench::condense_sole_box(h, 64, Form::dense));
      std::printf("setup dense %.4f %d %.3f %.2f %.1f\n", h, n, seconds_since(start),
                  dense->memory().total() / 1e6, bench::peak_megabytes());
    }
    const Eigen::MatrixX3d& x = factored.contact_positions();
    const Eigen::Vector3d origin = x.colwise().mean().transpose();
    Eigen::VectorXd load(3 * n), areas(n);
    factored.contact_load(Eigen::Vector3d(0, 0, 1), load);
    for (int k = 0; k < n; ++k)
      areas[k] = load[3 * k + 2];
    const Eigen::VectorXd area_weights = coupling::pressure_weights(areas);
    // The full sole's nodal forces under the rigid motions (dense route only).
    Eigen::MatrixXd f_full;
    if (dense)
      f_full = dense->compliance().ldlt().solve(coupling::rigid_motion_map(x, origin));
    const char* suffix[] = {"", "", "-area", "-bilinear"};
    // uniform, chebyshev, chebyshev with area shares, chebyshev bilinear (area weights)
    for (const int variant : {0, 1, 2, 3})
      for (int g = 2; g <= 32; g *= 2) {
        const auto spacing =
            variant == 0 ? coupling::GridSpacing::uniform : coupling::GridSpacing::chebyshev;
        const Eigen::VectorXd weights = variant >= 2 ? area_weights : Eigen::VectorXd();
        const auto basis =
            variant == 3 ? coupling::PatchBasis::bilinear : coupling::PatchBasis::constant;
        const auto shares = coupling::ReducedSole::grid_shares(x, g, g, spacing, basis, weights);
        if (shares.cols() >= n)
          break;
        start = std::chrono::steady_clock::now();
        const coupling::ReducedSole reduced(factored, shares);
        const double t_reduce = seconds_since(start);
        const double estimate =
            coupling::reduction_error_estimate(factored.rigid_motion_stiffness(), reduced, origin);
        double difference = -1;
        Eigen::Vector3d pressure = Eigen::Vector3d::Constant(-1);
        if (dense) {
          const coupling::ReducedSole from_c(x, dense->compliance(), shares);
          difference = (reduced.compliance() - from_c.compliance()).cwiseAbs().maxCoeff() /
                       from_c.compliance().cwiseAbs().maxCoeff();
          const Eigen::MatrixXd a(coupling::ReducedSole::aggregation(shares));
          const Eigen::MatrixXd f_r =
              a * from_c.compliance().ldlt().solve(
                      coupling::rigid_motion_map(from_c.patch_positions(), origin));
          const int motion[3] = {2, 4, 3}; // z, pitch (about y), roll (about x)
          for (int m = 0; m < 3; ++m) {
            double num = 0, den = 0;
            for (int k = 0; k < n; ++k) {
              const double p = f_full(3 * k + 2, motion[m]) / area_weights[k];
              const double p_r = f_r(3 * k + 2, motion[m]) / area_weights[k];
              num += area_weights[k] * (p - p_r) * (p - p_r);
              den += area_weights[k] * p * p;
            }
            pressure[m] = std::sqrt(num / den);
          }
        }
        std::printf("grid %.4f %s%s %d %d %.4g %.3f %.1e %.3g %.3g %.3g\n", h, name(spacing),
                    suffix[variant], g, reduced.n_patches(), estimate, t_reduce, difference,
                    pressure[0], pressure[1], pressure[2]);
        std::fflush(stdout);
      }
  }
  return 0;
}
