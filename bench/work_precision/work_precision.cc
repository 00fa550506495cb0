// Work-precision study of the humanoid scenes (issue 8): speed against error.
//
//   work_precision SCENE.prm [SCENE.prm ...] --out DIR [--repeat R] [--duration-drop S]
//                  [--duration-walk S] [--duration S] [--base-only] [--no-hyperelastic]
//                  [--only KNOB,...] [--mesh-sizes H,...] [--patches G,...]
//                  [--mesh-patches G,...] [--auto TOL,...] [--frame-every S]
//
// --mesh-sizes: the mesh knob's sizes (m; default the scene's x 4/3, 1, 2/3, 1/2); --patches:
// the sole model knob's grids (default 2, 3, 4, 6, 8); --mesh-patches G: one more knob per G,
// "mesh reduced GxG", the mesh sizes on a uniform G x G reduced sole in the constant basis
// (cost against contact nodes, bench/fine_sole/); --auto TOL: sole model rows "auto TOL"
// (Sole/Reduced patches = auto, Sole/Reduction tolerance = TOL); --graded-patches G and
// --graded-auto TOL: the same on Chebyshev-graded grids (Sole/Reduction spacing = chebyshev), rows
// "graded GxG", "graded auto TOL" (all these in the constant basis, with equal shares of a patch's
// force, Sole/Reduction weights = equal);
// --area-patches G and --area-auto TOL: graded grids with shares by node area (the scene
// default), rows "area GxG", "area auto TOL"; --bilinear-patches G: graded grids, shares by
// node area, Sole/Reduction basis = bilinear (one contact per grid vertex), rows "bilinear GxG";
// --bilinear-auto TOL and --pressure-auto TOL: auto on those grids, the tolerance on the stiffness
// estimate or on the pressure estimate (Sole/Reduction quantity = pressure), rows "bilinear auto
// TOL", "pressure auto TOL" (the CSV gives both estimates of every reduced row); --no-full: no
// full-sole row, the sole model knob's last row (the finest bilinear grid) is its reference (a
// mesh whose full sole does not fit, e.g. P2 at 5 mm).
// For each scene (run with Robot/Foot form = fem sole; durations: drop 0.5 s, walk the whole scene
// unless given), one knob at a time is varied from the scene's own setting, the others kept: sole
// mesh size, element degree, time step, the time step with the theta = 1/2 stepper on a
// Kelvin-Voigt sole ("damped theta 1/2 dt"), contact solver tolerance, sole model (reduced patches
// nx x ny, full) and the hyperelastic sole (Neo-Hookean, same E and nu, full sole;
// Sole/Recondensation tolerance = Sole/Check tolerance varied) and the viscoelastic sole (one Prony
// branch of half the scene's E relaxing in 4.5 ms: a standard linear solid whose instantaneous
// modulus is the scene's, docs/reproduction.md), its time step and its mesh size varied. --only
// runs the named knobs (and rigid feet). Each knob's finest value is that knob's reference; the row
// "linear vs hyper" is the linear full sole against the tightest hyperelastic run. Errors against
// the reference:
//   e_a  |max |a_z,waist| - ref| / ref                   (the paper's criterion)
//   e_u  |max normal sole deformation - ref| / ref       (max over nodes and time)
//   e_p  max_w |P_w - P_w,ref| / max_w |P_w,ref|, P_w the vertical contact impulse summed
//        over windows of the coarsest time step (the contact impulse per step, dt-independent)
// Companion measures, not the criterion: e_a_walk, the peak for t >= 0.1 s (walk: without the
// first step's settling onto the unloaded soles), and e_a_avg10, the peak of a_z averaged over
// centred 10 ms windows (independent of dt); both also for runs that fell, up to the earlier
// end of the two runs (compared_until_s).
// Issue 25's quantities (bench/fine_sole/): e_af, the filtered waist a_z peak; the worst
// landing's impulse and peak force; the centre-of-pressure path (m) and the nodal normal force
// field (relative, per frame every --frame-every s, worst and median), against the same
// reference (compare_issue25).
// Cost: loop wall seconds per simulated second, split into the stepper's phases
// (multibody::StepProfile) and "other" (reference, waist figures, CSV rows). One rigid-foot run
// gives the rigid cost. Each configuration is run R times, the minimum wall time kept; the
// loop's process CPU time (std::clock) is recorded too, less sensitive to a loaded machine,
// and the phase split is the steady_clock one.
// The dense-operator bandwidth check: time per contact solve against one read pass over the
// same number of bytes (the active patch blocks and G, 3n x rank), measured here.
// Writes DIR/work_precision.csv and prints the table. Never passes or fails.

#include "apps/condensed_sole_foot.h"
#include "apps/humanoid_simulation.h"
#include "apps/scene.h"
#include "apps/sole_patch_foot.h"
#include "coupling/reduced_sole.h"
#include "fem/exception_text.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

using namespace plantar;
using namespace plantar::app;

namespace {

struct Variant {
  std::string knob, value;
  std::function<void(Scene&)> apply;
  double time_step = 0; // filled from the scene
};

struct Result {
  std::string scene, knob, value, status = "ok";
  bool reference = false;
  double dt = 0, simulated = 0, wall = std::numeric_limits<double>::infinity(), setup = 0;
  double cpu = std::numeric_limits<double>::infinity(); // process CPU seconds of the loop
  multibody::StepProfile profile;
  int contacts_per_foot = 0, max_contacts = 0;
  double mean_iterations = 0;
  double direct_fraction = 0; // solves done by the direct all-sticking solve
  // Solves whose direct candidate was refused (a contact outside its cone / on the residual),
  // Gauss-Seidel sweeps per refused solve, local solves per sweep.
  double refused_cone_fraction = 0, refused_residual_fraction = 0;
  double sweeps_after_refusal = 0, local_solves_per_sweep = 0;
  double peak_az = 0, max_deformation = 0;
  double dissipated = 0;       // J, by viscoelastic soles
  std::vector<double> impulse; // vertical impulse per step, N s
  std::vector<double> vz;      // waist vertical velocity per step (world frame), m/s
  double e_a = NAN, e_u = NAN, e_p = NAN;
  // Companion measures (not the paper's criterion), over the time both runs simulated, from
  // t0 = 0.1 s for the walk (without the first steps' settling onto the soles), 0 otherwise:
  // e_w: peak |a_z| from t0; e_10: peak |a_z| averaged over centred 10 ms windows from t0.
  double horizon = 0, peak_walk = NAN, peak_avg10 = NAN, e_w = NAN, e_10 = NAN;
  double solve_time = NAN, pass_time = NAN, operator_bytes = 0;
  // Issue 25's quantities of interest. patches: the reduced grid (0: the full sole).
  int patches_x = 0, patches_y = 0;
  coupling::ReducedSole::ShareMatrix shares;    // n x P, of the patch forces (empty: full sole)
  double peak_af = 0;                           // filtered waist |a_z| peak, m/s^2
  std::array<std::vector<Landing>, 2> landings; // right, left
  Eigen::Matrix3Xd nodes;                       // contact points of a foot (sole frame, m)
  std::vector<double> frame_time;               // s
  std::array<std::vector<Eigen::VectorXd>, 2> normal_force; // per frame, per contact, N
  std::array<std::vector<Eigen::Vector2d>, 2> cop;          // per frame, world x-y, m
  double kept_bytes = 0;                                    // the feet's compliance operators
  double reduction_estimate = 0; // coupling::reduction_error_estimate (0: full)
  double pressure_estimate = 0;  // coupling::pressure_error_estimate (0: full)
  double e_af = NAN, e_j = NAN, e_f = NAN, e_cop = NAN, e_pf = NAN, e_pf_median = NAN;
  // The reference's field at the same frames projected on the reduced sole's shares (least
  // squares, min_F ||S F - f_ref||): the field's representation error alone, worst and median.
  double e_pf_best = NAN, e_pf_best_median = NAN;
};

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Minimum time (s) of one read pass over @p bytes (sum of doubles), after a warm-up.
double read_pass_time(double bytes) {
  const auto n = static_cast<std::size_t>(std::max(1.0, bytes / 8));
  std::vector<double> buffer(n, 1.0);
  volatile double sink = 0;
  double best = 1e9;
  const int inner = std::max<int>(1, static_cast<int>(2e6 / n));
  for (int r = 0; r < 20; ++r) {
    const double t0 = now();
    for (int i = 0; i < inner; ++i) {
      double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
      std::size_t k = 0;
      for (; k + 4 <= n; k += 4) {
        s0 += buffer[k];
        s1 += buffer[k + 1];
        s2 += buffer[k + 2];
        s3 += buffer[k + 3];
      }
      for (; k < n; ++k)
        s0 += buffer[k];
      sink = sink + s0 + s1 + s2 + s3;
      buffer[i % n] += 1e-300; // keep the loop from being hoisted
    }
    best = std::min(best, (now() - t0) / inner);
  }
  return best;
}

/// Runs @p scene @p repeat times into @p result; every @p frame_every seconds the feet's normal
/// contact forces and centres of pressure are kept (issue 25's field and path errors).
void run_one(const Scene& scene, Result& result, int repeat, double frame_every) {
  for (int r = 0; r < repeat; ++r) {
    try {
      HumanoidSimulation simulation(scene);
      const bool fem = scene.robot.foot_form == FootForm::fem_sole;
      const double dt = scene.simulation.time_step;
      std::vector<double> impulse;
      impulse.reserve(simulation.n_steps() + 1);
      double max_deformation = 0;
      const long frame_steps = std::max(1L, std::lround(frame_every / dt));
      long step = 0;
      result.frame_time.clear();
      for (int foot = 0; foot < 2; ++foot) {
        result.normal_force[foot].clear();
        result.cop[foot].clear();
      }
      std::string failure;
      const std::clock_t cpu_start = std::clock();
      try {
        simulation.run([&](const HumanoidSimulation& s) {
          const multibody::Stepper& stepper = s.stepper();
          impulse.push_back(stepper.total_contact_force().z() * dt);
          if (!fem)
            return;
          const auto& sole = dynamic_cast<const SolePatchFoot&>(s.foot_model());
          for (int foot = 0; foot < 2; ++foot) {
            const Eigen::VectorXd& u = sole.pad(foot).displacement(); // (n, t1, t2) per node
            for (Eigen::Index k = 0; k < u.size(); k += 3)
              max_deformation = std::max(max_deformation, std::abs(u[k]));
          }
          if (++step % frame_steps != 0)
            return;
          result.frame_time.push_back(step * dt);
          const TimeSeries& contacts = s.contact_series();
          const int row = contacts.n_rows() - 1;
          for (int foot = 0; foot < 2; ++foot) {
            const Eigen::VectorXd& f = sole.pad(foot).force(); // (n, t1, t2) per node
            result.normal_force[foot].push_back(
                Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<3>>(f.data(),
                                                                            f.size() / 3));
            const std::string side = foot == 0 ? "right_" : "left_";
            result.cop[foot].emplace_back(
                row >= 0 ? contacts(row, contacts.column(side + "copx")) : NAN,
                row >= 0 ? contacts(row, contacts.column(side + "copy")) : NAN);
          }
        });
      } catch (const std::exception& e) {
        failure = fem::exception_text(e); // keep the cost up to the failure
      }
      const double cpu = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
      const HumanoidSummary& summary = simulation.summary();
      result.cpu = std::min(result.cpu, cpu);
      if (summary.loop_wall_time < result.wall) {
        result.wall = summary.loop_wall_time;
        result.setup = summary.setup_wall_time;
        result.profile = simulation.stepper().profile();
      }
      result.dt = dt;
      result.simulated = summary.simulated_time;
      result.contacts_per_foot = fem ? summary.n_sole_nodes : 8;
      result.max_contacts = summary.max_active_contacts;
      result.mean_iterations =
          summary.n_solves > 0 ? double(summary.solver_iterations) / summary.n_solves : 0;
      result.direct_fraction =
          summary.n_solves > 0 ? double(summary.n_direct_solves) / summary.n_solves : 0;
      const int n_refused = summary.n_direct_refused_cone + summary.n_direct_refused_residual;
      result.refused_cone_fraction =
          summary.n_solves > 0 ? double(summary.n_direct_refused_cone) / summary.n_solves : 0;
      result.refused_residual_fraction =
          summary.n_solves > 0 ? double(summary.n_direct_refused_residual) / summary.n_solves : 0;
      result.sweeps_after_refusal =
          n_refused > 0 ? double(summary.iterations_after_refusal) / n_refused : 0;
      result.local_solves_per_sweep =
          summary.solver_iterations > 0
              ? double(summary.n_local_solves) / double(summary.solver_iterations)
              : 0;
      result.peak_az = summary.max_waist_acceleration_z;
      result.peak_af = summary.max_waist_acceleration_z_filtered;
      for (int foot = 0; foot < 2; ++foot)
        result.landings[foot] = simulation.landings(foot);
      result.patches_x = summary.sole_reduction_x;
      result.patches_y = summary.sole_reduction_y;
      if (const auto* foot = dynamic_cast<const CondensedSoleFoot*>(&simulation.foot_model()))
        if (foot->reduced())
          result.shares = foot->reduced()->shares();
      result.reduction_estimate = summary.sole_reduction_estimate;
      result.pressure_estimate = summary.sole_reduction_pressure_estimate;
      if (fem) {
        const auto& sole = dynamic_cast<const SolePatchFoot&>(simulation.foot_model());
        result.nodes = sole.contact_points();
        result.kept_bytes = 0;
        for (int foot = 0; foot < 2; ++foot)
          result.kept_bytes += 8.0 * double(sole.pad(foot).compliance().size());
      }
      result.max_deformation = max_deformation;
      result.dissipated = summary.sole_dissipated_energy;
      result.impulse = impulse;
      const TimeSeries& waist = simulation.waist_series();
      result.vz.clear();
      if (waist.n_rows() > 0) {
        const int c = waist.column("vz");
        for (int k = 0; k < waist.n_rows(); ++k)
          result.vz.push_back(waist(k, c));
      }
      const auto& p = result.profile;
      if (p.n_solves > 0) {
        // Dense operator of an average solve: rows x rank of G (6 per contact body) plus the
        // active patch blocks.
        const double rows = double(p.n_solve_rows) / p.n_solves;
        const double nv = simulation.stepper().problem().rigid_rank();
        const double patch_rows = 3.0 * result.contacts_per_foot;
        const double n_patches = fem ? rows / patch_rows : 0;
        result.operator_bytes = 8 * (rows * nv + n_patches * patch_rows * patch_rows);
        result.solve_time = p.contact_solve / p.n_solves;
      }
      if (!failure.empty())
        throw std::runtime_error(failure);
    } catch (const std::exception& e) {
      result.status = fem::exception_text(e);
      std::replace(result.status.begin(), result.status.end(), ',', ';');
      std::replace(result.status.begin(), result.status.end(), '\n', ' ');
      return;
    }
  }
  if (result.operator_bytes > 0)
    result.pass_time = read_pass_time(result.operator_bytes);
}

/// Vertical impulse summed over windows of @p window seconds.
std::vector<double> windowed(const std::vector<double>& impulse, double dt, double window) {
  const int per = std::max(1, static_cast<int>(std::lround(window / dt)));
  std::vector<double> out((impulse.size() + per - 1) / per, 0.0);
  for (std::size_t n = 0; n < impulse.size(); ++n)
    out[n / per] += impulse[n];
  return out;
}

/// Peaks of |a_z| of the waist over [t0, t1]: raw backward difference and the centred 10 ms
/// average (v(t + 5 ms) - v(t - 5 ms)) / 10 ms; v = 0 before the first step.
std::pair<double, double> peaks(const std::vector<double>& vz, double dt, double t0, double t1) {
  const auto v = [&](long k) { return k <= 0 ? 0.0 : vz[k - 1]; }; // v(k dt)
  const long n = static_cast<long>(vz.size()), h = std::max(1L, std::lround(0.005 / dt));
  double raw = 0, avg = 0;
  for (long k = 1; k <= n; ++k) {
    const double t = k * dt;
    if (t < t0 - 1e-12 || t > t1 + 1e-12)
      continue;
    raw = std::max(raw, std::abs(v(k) - v(k - 1)) / dt);
    if (k - h >= 0 && k + h <= n)
      avg = std::max(avg, std::abs(v(k + h) - v(k - h)) / (2 * h * dt));
  }
  return {raw, avg};
}

/// Largest relative difference of a landing figure over the landings both runs have (per foot,
/// in order).
double landing_error(const Result& r, const Result& ref, double Landing::*figure) {
  double worst = NAN;
  for (int foot = 0; foot < 2; ++foot)
    for (std::size_t k = 0; k < std::min(r.landings[foot].size(), ref.landings[foot].size()); ++k) {
      const double a = r.landings[foot][k].*figure, b = ref.landings[foot][k].*figure;
      const double e = std::abs(a - b) / std::abs(b);
      worst = std::isnan(worst) ? e : std::max(worst, e);
    }
  return worst;
}

/// Issue 25's errors of @p r against @p ref (same time step): filtered peak a_z, landing impulse
/// and peak force (the worst landing), centre-of-pressure path (the largest distance, m, over
/// the frames where both runs load the foot with more than 5 % of the reference's largest
/// foot force) and the contact
/// force field: the relative Euclidean norm of the nodal normal forces' difference per frame
/// (frames where the reference foot carries > 5 % of its largest force), its maximum and median. A
/// reduced run's patch force F_j is spread over its nodes by their shares
/// (coupling/reduced_sole.h); the field error needs the reference on the same mesh (the full
/// sole, or a reduced one whose forces are spread the same way), and e_pf_best is the error of
/// the reference field's least-squares projection on the run's shares.
void compare_issue25(Result& r, const Result& ref) {
  if (ref.peak_af > 0)
    r.e_af = std::abs(r.peak_af - ref.peak_af) / ref.peak_af;
  r.e_j = landing_error(r, ref, &Landing::impulse);
  r.e_f = landing_error(r, ref, &Landing::peak_force);
  if (r.dt != ref.dt || r.frame_time.empty() || ref.frame_time.empty())
    return;
  double loaded = 0; // N: 5 % of the reference's largest foot force
  for (int foot = 0; foot < 2; ++foot)
    for (const Eigen::VectorXd& f : ref.normal_force[foot])
      loaded = std::max(loaded, 0.05 * f.sum());
  const std::size_t frames = std::min(r.frame_time.size(), ref.frame_time.size());
  double cop = 0;
  for (int foot = 0; foot < 2; ++foot)
    for (std::size_t k = 0; k < frames; ++k)
      if (r.normal_force[foot][k].sum() > loaded && ref.normal_force[foot][k].sum() > loaded)
        cop = std::max(cop, (r.cop[foot][k] - ref.cop[foot][k]).norm());
  r.e_cop = cop;
  // Nodes of the mesh both runs share: the reference's, or its reduced sole's full node set.
  const Eigen::Index mesh_nodes = ref.patches_x > 0 ? ref.shares.rows() : ref.nodes.cols();
  const bool same_mesh = r.nodes.cols() > 0 && (r.patches_x > 0 ? r.shares.rows() == mesh_nodes
                                                                : r.nodes.cols() == mesh_nodes);
  if (!same_mesh)
    return;
  std::vector<double> errors, best;
  Eigen::VectorXd spread(mesh_nodes), b(mesh_nodes);
  Eigen::LDLT<Eigen::MatrixXd> normal_equations;
  if (r.patches_x > 0)
    normal_equations.compute(Eigen::MatrixXd(r.shares.transpose() * r.shares));
  for (int foot = 0; foot < 2; ++foot)
    for (std::size_t k = 0; k < frames; ++k) {
      if (ref.normal_force[foot][k].sum() <= loaded)
        continue;
      if (ref.patches_x > 0)
        b = ref.shares * ref.normal_force[foot][k];
      else
        b = ref.normal_force[foot][k];
      const Eigen::VectorXd& a = r.normal_force[foot][k];
      if (r.patches_x > 0)
        spread = r.shares * a;
      else
        spread = a;
      errors.push_back((spread - b).norm() / b.norm());
      if (r.patches_x > 0) {
        const Eigen::VectorXd projected =
            r.shares * normal_equations.solve(Eigen::VectorXd(r.shares.transpose() * b));
        best.push_back((projected - b).norm() / b.norm());
      }
    }
  if (errors.empty())
    return;
  std::sort(errors.begin(), errors.end());
  r.e_pf = errors.back();
  r.e_pf_median = errors[errors.size() / 2];
  if (best.empty())
    return;
  std::sort(best.begin(), best.end());
  r.e_pf_best = best.back();
  r.e_pf_best_median = best[best.size() / 2];
}

void compare(Result& r, const Result& ref, double window) {
  // The companion measures also when a run failed (fell): over the time both simulated.
  if (!r.vz.empty() && !ref.vz.empty()) {
    r.horizon = std::min(r.vz.size() * r.dt, ref.vz.size() * ref.dt);
    const double t0 = r.scene == "walk" ? 0.1 : 0.0;
    const auto [w, a10] = peaks(r.vz, r.dt, t0, r.horizon);
    const auto [w_ref, a10_ref] = peaks(ref.vz, ref.dt, t0, r.horizon);
    r.peak_walk = w;
    r.peak_avg10 = a10;
    r.e_w = std::abs(w - w_ref) / w_ref;
    r.e_10 = std::abs(a10 - a10_ref) / a10_ref;
  }
  if (r.status != "ok" || ref.status != "ok")
    return;
  r.e_a = std::abs(r.peak_az - ref.peak_az) / ref.peak_az;
  r.e_u = ref.max_deformation > 0
              ? std::abs(r.max_deformation - ref.max_deformation) / ref.max_deformation
              : NAN;
  const auto a = windowed(r.impulse, r.dt, window), b = windowed(ref.impulse, ref.dt, window);
  double worst = 0, scale = 0;
  for (std::size_t w = 0; w < std::min(a.size(), b.size()); ++w) {
    worst = std::max(worst, std::abs(a[w] - b[w]));
    scale = std::max(scale, std::abs(b[w]));
  }
  r.e_p = scale > 0 ? worst / scale : NAN;
  compare_issue25(r, ref);
}

std::string fmt(double x, const char* f = "%.4g") {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, f, x);
  return buffer;
}

/// The scene's sole as a Neo-Hookean hyperelastic sole of the same small-strain E, nu
/// (Sole/Model = hyperelastic, full sole), with Sole/Recondensation tolerance and Sole/Check
/// tolerance both set to @p tolerance.
void make_hyperelastic(Scene& s, double tolerance) {
  std::string& m = s.sole.materials;
  const auto law = m.find("law=linear");
  if (law != std::string::npos)
    m.replace(law, 10, "law=neo_hookean");
  else if (m.find("law=") == std::string::npos) {
    const auto colon = m.find(':');
    m.insert(colon == std::string::npos ? 0 : colon + 1, " law=neo_hookean,");
  }
  s.sole.model = "hyperelastic";
  s.sole.recondensation_tolerance = tolerance;
  s.sole.check_tolerance = tolerance;
  s.sole_reduction = {};
}

/// The scene's linear sole "name: law=linear, E=..., nu=..." as the standard linear solid
/// "name: law=prony, E=E/2, nu=nu, E1=E/2, tau1=4.5e-3": instantaneous modulus E, long-term E/2,
/// loss factor peak 0.354 at 25 Hz (docs/reproduction.md). Throws if the sole has no E= or nu=.
void make_viscoelastic(Scene& s) {
  const std::string& m = s.sole.materials;
  const auto value = [&](const std::string& key) {
    const auto at = m.find(" " + key + "=");
    if (at == std::string::npos)
      throw std::invalid_argument("work_precision: Sole/Materials '" + m + "' has no " + key + "=");
    return std::stod(m.substr(at + key.size() + 2));
  };
  const double e = value("E"), nu = value("nu");
  const auto colon = m.find(':');
  const std::string name = colon == std::string::npos ? "rubber" : m.substr(0, colon);
  s.sole.materials = name + ": law=prony, E=" + fmt(e / 2, "%.17g") + ", nu=" + fmt(nu, "%.17g") +
                     ", E1=" + fmt(e / 2, "%.17g") + ", tau1=4.5e-3";
  s.sole.damping_time = 0;
  s.sole_reduction = {};
}

/// The numbers of a comma-separated @p list (throws on a bad number).
std::vector<double> number_list(const std::string& list) {
  std::vector<double> out;
  for (std::size_t start = 0; start < list.size();) {
    const auto comma = std::min(list.find(',', start), list.size());
    out.push_back(std::stod(list.substr(start, comma - start)));
    start = comma + 1;
  }
  return out;
}

} // namespace

int main(int argc, char** argv) {
  std::vector<std::filesystem::path> scenes;
  std::filesystem::path out = "work_precision";
  int repeat = 1;
  bool base_only = false;   // --base-only: the scene's own setting (fem sole) and rigid feet
  bool hyperelastic = true; // --no-hyperelastic: skip the hyperelastic-sole knob
  double duration_drop = 0.5, duration_walk = 0;
  std::vector<std::string> only;       // --only: the knobs to run (all when empty)
  double duration = 0;                 // --duration: every scene type (overrides the two above)
  double frame_every = 0.01;           // --frame-every: s between the kept force fields
  std::vector<double> mesh_sizes;      // --mesh-sizes: the mesh knob's sizes (m), else h0 x factors
  std::vector<double> patches;         // --patches: the sole model knob's grids g x g
  std::vector<double> mesh_patches;    // --mesh-patches: a mesh knob per reduced grid g x g
  std::vector<double> auto_tolerances; // --auto: sole model rows with Reduced patches = auto
  std::vector<double> graded_patches;  // --graded-patches: sole model rows, Chebyshev grids
  std::vector<double> graded_auto;     // --graded-auto: auto rows on Chebyshev grids
  std::vector<double> area_patches;    // --area-patches: Chebyshev grids, shares by node area
  std::vector<double> area_auto;       // --area-auto: auto rows of the same
  std::vector<double> bilinear_patches; // --bilinear-patches: graded grids, bilinear basis
  std::vector<double> bilinear_auto;    // --bilinear-auto: auto rows of the same
  std::vector<double> pressure_auto;    // --pressure-auto: the same on the pressure estimate
  bool full_sole = true;                // --no-full: false
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc)
      out = argv[++i];
    else if (a == "--repeat" && i + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--duration-drop" && i + 1 < argc)
      duration_drop = std::atof(argv[++i]);
    else if (a == "--base-only")
      base_only = true;
    else if (a == "--no-hyperelastic")
      hyperelastic = false;
    else if (a == "--duration-walk" && i + 1 < argc)
      duration_walk = std::atof(argv[++i]);
    else if (a == "--duration" && i + 1 < argc)
      duration = std::atof(argv[++i]);
    else if (a == "--frame-every" && i + 1 < argc)
      frame_every = std::atof(argv[++i]);
    else if (a == "--mesh-sizes" && i + 1 < argc)
      mesh_sizes = number_list(argv[++i]);
    else if (a == "--patches" && i + 1 < argc)
      patches = number_list(argv[++i]);
    else if (a == "--mesh-patches" && i + 1 < argc)
      mesh_patches = number_list(argv[++i]);
    else if (a == "--auto" && i + 1 < argc)
      auto_tolerances = number_list(argv[++i]);
    else if (a == "--graded-patches" && i + 1 < argc)
      graded_patches = number_list(argv[++i]);
    else if (a == "--graded-auto" && i + 1 < argc)
      graded_auto = number_list(argv[++i]);
    else if (a == "--area-patches" && i + 1 < argc)
      area_patches = number_list(argv[++i]);
    else if (a == "--area-auto" && i + 1 < argc)
      area_auto = number_list(argv[++i]);
    else if (a == "--bilinear-patches" && i + 1 < argc)
      bilinear_patches = number_list(argv[++i]);
    else if (a == "--bilinear-auto" && i + 1 < argc)
      bilinear_auto = number_list(argv[++i]);
    else if (a == "--pressure-auto" && i + 1 < argc)
      pressure_auto = number_list(argv[++i]);
    else if (a == "--no-full")
      full_sole = false;
    else if (a == "--only" && i + 1 < argc) {
      std::string list = argv[++i];
      for (std::size_t start = 0; start <= list.size();) {
        const auto comma = std::min(list.find(',', start), list.size());
        only.push_back(list.substr(start, comma - start));
        start = comma + 1;
      }
    } else if (!a.empty() && a[0] != '-')
      scenes.emplace_back(a);
    else {
      std::cerr << "usage: work_precision SCENE.prm ... --out DIR [--repeat R] "
                   "[--duration-drop S] [--duration-walk S] [--duration S] [--base-only] "
                   "[--no-hyperelastic] [--only KNOB,...] [--mesh-sizes H,...] [--patches G,...] "
                   "[--mesh-patches G,...] [--auto TOL,...] [--graded-patches G,...] "
                   "[--graded-auto TOL,...] [--area-patches G,...] [--area-auto TOL,...] "
                   "[--bilinear-patches G,...] [--bilinear-auto TOL,...] "
                   "[--pressure-auto TOL,...] [--no-full] [--frame-every S]\n";
      return 1;
    }
  }
  if (scenes.empty()) {
    std::cerr << "work_precision: no scene given\n";
    return 1;
  }
  std::filesystem::create_directories(out);
  std::vector<Result> results;
  // The CSV, rewritten after every knob (a run killed later keeps the knobs done), by a
  // temporary file and a rename.
  const auto write_csv = [&]() {
    const std::filesystem::path path = out / "work_precision.csv",
                                tmp = out / "work_precision.csv.tmp";
    {
      std::ofstream csv(tmp);
      csv << "scene,knob,value,reference,status,dt,simulated_s,contacts_per_foot,max_contacts,"
             "mean_iterations,cpu_per_sim_s,wall_per_sim_s,dynamics,contact_build,sole_update,"
             "contact_"
             "solve,"
             "other,setup_s,peak_az,max_deformation,e_a,e_u,e_p,solve_us,pass_us,solve_over_pass,"
             "compared_until_s,peak_az_walk,peak_az_avg10,e_a_walk,e_a_avg10,direct_fraction,"
             "refused_cone_fraction,refused_residual_fraction,sweeps_after_refusal,"
             "local_solves_per_sweep,sole_dissipated_J,peak_az_filtered,e_af,e_landing_impulse,"
             "e_landing_peak_force,e_cop_m,e_field_max,e_field_median,kept_MB,n_landings,"
             "reduction_estimate,pressure_estimate,e_field_best_max,e_field_best_median\n";
      for (const auto& r : results) {
        const double sim = std::max(r.simulated, 1e-12);
        const auto& p = r.profile;
        const double other = r.wall - p.total();
        csv << r.scene << "," << r.knob << "," << r.value << "," << r.reference << "," << r.status
            << "," << r.dt << "," << r.simulated << "," << r.contacts_per_foot << ","
            << r.max_contacts << "," << r.mean_iterations << "," << r.cpu / sim << ","
            << r.wall / sim << "," << p.dynamics / sim << "," << p.contact_build / sim << ","
            << p.sole_update / sim << "," << p.contact_solve / sim << "," << other / sim << ","
            << r.setup << "," << r.peak_az << "," << r.max_deformation << "," << r.e_a << ","
            << r.e_u << "," << r.e_p << "," << 1e6 * r.solve_time << "," << 1e6 * r.pass_time << ","
            << r.solve_time / r.pass_time << "," << r.horizon << "," << r.peak_walk << ","
            << r.peak_avg10 << "," << r.e_w << "," << r.e_10 << "," << r.direct_fraction << ","
            << r.refused_cone_fraction << "," << r.refused_residual_fraction << ","
            << r.sweeps_after_refusal << "," << r.local_solves_per_sweep << "," << r.dissipated
            << "," << r.peak_af << "," << r.e_af << "," << r.e_j << "," << r.e_f << "," << r.e_cop
            << "," << r.e_pf << "," << r.e_pf_median << "," << r.kept_bytes / 1048576.0 << ","
            << r.landings[0].size() + r.landings[1].size() << "," << r.reduction_estimate << ","
            << r.pressure_estimate << "," << r.e_pf_best << "," << r.e_pf_best_median << "\n";
      }
    }
    std::filesystem::rename(tmp, path);
  };
  for (const auto& file : scenes) {
    dealii::ParameterHandler prm;
    Scene base;
    try {
      base = load_scene(file, prm);
    } catch (const std::exception& e) {
      std::cerr << fem::exception_text(e) << "\n";
      return 1;
    }
    base.robot.foot_form = FootForm::fem_sole;
    base.output.write_vtu = false;
    const double scene_duration = duration > 0                   ? duration
                                  : base.type == SceneType::drop ? duration_drop
                                                                 : duration_walk;
    if (scene_duration > 0)
      base.simulation.duration = scene_duration;
    const double h0 = base.sole.mesh_size, dt0 = base.simulation.time_step;
    std::vector<std::vector<Variant>> knobs;
    std::vector<double> sizes = mesh_sizes;
    if (sizes.empty())
      for (double f : {4.0 / 3.0, 1.0, 2.0 / 3.0, 0.5})
        sizes.push_back(h0 * f);
    {
      std::vector<Variant> v;
      for (double h : sizes)
        v.push_back({"mesh size", fmt(h, "%.3g"), [h](Scene& s) { s.sole.mesh_size = h; }});
      knobs.push_back(v);
    }
    for (const double g : mesh_patches) {
      // The mesh knob on a reduced sole of g x g patches (cost against contact nodes).
      const int n = static_cast<int>(g);
      std::vector<Variant> v;
      for (double h : sizes)
        v.push_back({"mesh reduced " + std::to_string(n) + "x" + std::to_string(n), fmt(h, "%.3g"),
                     [h, n](Scene& s) {
                       s.sole.mesh_size = h;
                       s.sole_reduction.patches_x = s.sole_reduction.patches_y = n;
                       s.sole_reduction.spacing = coupling::GridSpacing::uniform;
                       s.sole_reduction.basis = coupling::PatchBasis::constant;
                     }});
      knobs.push_back(v);
    }
    knobs.push_back({{"degree", "1", [](Scene& s) { s.sole.degree = 1; }},
                     {"degree", "2", [](Scene& s) { s.sole.degree = 2; }}});
    {
      std::vector<Variant> v;
      for (double f : {4.0, 2.0, 1.0, 0.5, 0.25, 0.125})
        v.push_back({"time step", fmt(dt0 * f, "%.3g"),
                     [d = dt0 * f](Scene& s) { s.simulation.time_step = d; }});
      knobs.push_back(v);
    }
    {
      // The time step with the theta = 1/2 stepper on a Kelvin-Voigt sole (the scene's
      // Sole/Damping time, 1 ms if it has none): the setting whose peak converges in dt
      // (docs/performance.md, walk_damped_fast.prm).
      const double beta = base.sole.damping_time > 0 ? base.sole.damping_time : 1e-3;
      std::vector<Variant> v;
      for (double f : {2.0, 1.0, 0.8, 0.5, 0.25, 0.125})
        v.push_back({"damped theta 1/2 dt", fmt(dt0 * f, "%.3g"), [d = dt0 * f, beta](Scene& s) {
                       s.simulation.time_step = d;
                       s.simulation.theta = 0.5;
                       s.sole.damping_time = beta;
                     }});
      knobs.push_back(v);
    }
    {
      std::vector<Variant> v;
      for (double tol : {1e-3, 1e-4, 1e-6, 1e-8, 1e-10})
        v.push_back({"tolerance", fmt(tol, "%.0e"), [tol](Scene& s) {
                       s.contact.tolerance = tol;
                       s.contact.failure_residual = std::max(s.contact.failure_residual, 10 * tol);
                     }});
      knobs.push_back(v);
    }
    {
      std::vector<Variant> v;
      if (patches.empty())
        patches = {2, 3, 4, 6, 8};
      // Reduced soles: given grids and auto tolerances, on uniform and graded grids.
      // Equal shares of a patch's force (reduced, graded) or shares by node area (area).
      const auto add_reduced = [&v](const std::string& prefix, coupling::GridSpacing spacing,
                                    bool area, const std::vector<double>& grids,
                                    const std::vector<double>& tolerances,
                                    coupling::PatchBasis basis = coupling::PatchBasis::constant,
                                    coupling::ReductionQuantity quantity =
                                        coupling::ReductionQuantity::stiffness) {
        for (const double p : grids)
          v.push_back({"sole model", prefix + std::to_string(int(p)) + "x" + std::to_string(int(p)),
                       [g = int(p), spacing, area, basis](Scene& s) {
                         s.sole_reduction = {};
                         s.sole_reduction.patches_x = s.sole_reduction.patches_y = g;
                         s.sole_reduction.spacing = spacing;
                         s.sole_reduction.area_weights = area;
                         s.sole_reduction.basis = basis;
                       }});
        for (const double tolerance : tolerances)
          v.push_back({"sole model", prefix + "auto " + fmt(tolerance, "%.3g"),
                       [tolerance, spacing, area, basis, quantity](Scene& s) {
                         s.sole_reduction = {};
                         s.sole_reduction.automatic = true;
                         s.sole_reduction.tolerance = tolerance;
                         s.sole_reduction.spacing = spacing;
                         s.sole_reduction.area_weights = area;
                         s.sole_reduction.basis = basis;
                         s.sole_reduction.quantity = quantity;
                       }});
      };
      const auto uniform = coupling::GridSpacing::uniform;
      const auto graded = coupling::GridSpacing::chebyshev;
      add_reduced("reduced ", uniform, false, patches, {});
      add_reduced("", uniform, false, {}, auto_tolerances);
      add_reduced("graded ", graded, false, graded_patches, graded_auto);
      add_reduced("area ", graded, true, area_patches, area_auto);
      add_reduced("bilinear ", graded, true, bilinear_patches, bilinear_auto,
                  coupling::PatchBasis::bilinear);
      add_reduced("pressure ", graded, true, {}, pressure_auto, coupling::PatchBasis::bilinear,
                  coupling::ReductionQuantity::pressure);
      if (full_sole)
        v.push_back({"sole model", "full", [](Scene& s) { s.sole_reduction = {}; }});
      knobs.push_back(v);
    }
    if (hyperelastic) {
      // The Neo-Hookean sole of the same small-strain E, nu (full sole: no reduced patches),
      // its two tolerances varied together; the tightest is the reference. The last row is the
      // linear full sole compared with that reference: the nonlinear-vs-linear difference.
      std::vector<Variant> v;
      for (double tol : {0.1, 0.03, 0.01, 0.003})
        v.push_back(
            {"hyperelastic tol", fmt(tol, "%.3g"), [tol](Scene& s) { make_hyperelastic(s, tol); }});
      knobs.push_back(v);
    }
    {
      // The viscoelastic sole (make_viscoelastic): its time step and its mesh size; the
      // finest of each is its reference.
      std::vector<Variant> v;
      for (double f : {2.0, 1.0, 0.5, 0.25, 0.125})
        v.push_back({"visco dt", fmt(dt0 * f, "%.3g"), [d = dt0 * f](Scene& s) {
                       make_viscoelastic(s);
                       s.simulation.time_step = d;
                     }});
      knobs.push_back(v);
      v.clear();
      for (double f : {4.0 / 3.0, 1.0, 2.0 / 3.0, 0.5})
        v.push_back({"visco mesh", fmt(h0 * f, "%.3g"), [h = h0 * f](Scene& s) {
                       make_viscoelastic(s);
                       s.sole.mesh_size = h;
                     }});
      knobs.push_back(v);
    }
    if (!only.empty())
      knobs.erase(std::remove_if(knobs.begin(), knobs.end(),
                                 [&](const std::vector<Variant>& k) {
                                   const std::string& name = k.front().knob;
                                   return std::find(only.begin(), only.end(), name) == only.end() &&
                                          !(name.rfind("mesh reduced", 0) == 0 &&
                                            std::find(only.begin(), only.end(), "mesh reduced") !=
                                                only.end());
                                 }),
                  knobs.end());
    if (base_only)
      knobs = {{{"base", "scene", [](Scene&) {}}}};
    const double window = 4 * dt0; // the coarsest time step of the sweep
    for (const auto& knob : knobs) {
      std::vector<Result> rows;
      for (const auto& variant : knob) {
        Scene scene = base;
        variant.apply(scene);
        Result r;
        r.scene = to_string(base.type);
        r.knob = variant.knob;
        r.value = variant.value;
        std::cerr << to_string(base.type) << ": " << r.knob << " = " << r.value << " ..."
                  << std::flush;
        run_one(scene, r, repeat, frame_every);
        std::cerr << " " << r.status << ", " << fmt(r.wall / std::max(r.simulated, 1e-12))
                  << " s/s\n";
        rows.push_back(r);
      }
      rows.back().reference = true;
      for (auto& r : rows)
        compare(r, rows.back(), window);
      results.insert(results.end(), rows.begin(), rows.end());
      write_csv();
    }
    if (hyperelastic && only.empty()) {
      // Nonlinear against linear: the linear full sole against the hyperelastic reference.
      const Result *linear = nullptr, *nonlinear = nullptr;
      for (const auto& r : results)
        if (r.scene == to_string(base.type) && r.knob == "sole model" && r.value == "full")
          linear = &r;
        else if (r.scene == to_string(base.type) && r.knob == "hyperelastic tol" && r.reference)
          nonlinear = &r;
      if (linear && nonlinear) {
        Result r = *linear;
        r.knob = "linear vs hyper";
        r.value = "linear full";
        r.reference = false;
        compare(r, *nonlinear, window);
        results.push_back(r);
      }
    }
    Scene rigid = base;
    rigid.robot.foot_form = FootForm::rigid;
    Result r;
    r.scene = to_string(base.type);
    r.knob = "rigid feet";
    r.value = "rigid";
    r.reference = true;
    run_one(rigid, r, repeat, frame_every);
    results.push_back(r);
  }
  write_csv();

  write_csv();
  std::printf(
      "%-5s %-11s %-13s %8s %8s %6s %7s %8s %8s %8s %8s %8s %9s %9s %9s %8s %6s %9s %9s %6s\n",
      "scene", "knob", "value", "cpu/sim", "wall/sim", "x_rt", "dyn", "build", "sole", "solve",
      "other", "peak_az", "e_a", "e_u", "e_p", "solve_us", "ratio", "e_a_walk", "e_a_avg10",
      "until");
  for (const auto& r : results) {
    const double sim = std::max(r.simulated, 1e-12);
    const auto& p = r.profile;
    const double other = r.wall - p.total();
    std::printf(
        "%-5s %-11s %-13s %8.3f %8.3f %6.1f %7.3f %8.3f %8.3f %8.3f %8.3f %8.2f %9.2e %9.2e "
        "%9.2e %8.1f %6.1f %9.2e %9.2e %6.2f %s\n",
        r.scene.c_str(), r.knob.c_str(), r.value.c_str(), r.cpu / sim, r.wall / sim, sim / r.cpu,
        p.dynamics / sim, p.contact_build / sim, p.sole_update / sim, p.contact_solve / sim,
        other / sim, r.peak_az, r.e_a, r.e_u, r.e_p, 1e6 * r.solve_time, r.solve_time / r.pass_time,
        r.e_w, r.e_10, r.horizon, r.status == "ok" ? "" : r.status.c_str());
  }
  return 0;
}
