#include "contact/local_contact_solve.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

namespace plantar::contact {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct GridTable {
  double cos[64], sin[64];
  GridTable() {
    for (int i = 0; i < 64; ++i) {
      cos[i] = std::cos(2.0 * kPi * i / 64);
      sin[i] = std::sin(2.0 * kPi * i / 64);
    }
  }
};

// Quantities of the sliding candidate at angle phi.
// den = A_nn + mu A_nt d;  p_n = -(q_n + b)/den;  den v_t = den q_t - (q_n + b)(A_tn + mu A_tt d).
double slide_function_cs(const Eigen::Matrix3d& a, const Eigen::Vector3d& q, double qn_b, double mu,
                         double c, double s) {
  const Eigen::Vector2d d(c, s);
  const double den = a(0, 0) + mu * (a(0, 1) * d[0] + a(0, 2) * d[1]);
  const Eigen::Vector2d a_tn(a(1, 0), a(2, 0));
  const Eigen::Vector2d scaled_vt =
      den * q.tail<2>() - qn_b * (a_tn + mu * a.bottomRightCorner<2, 2>() * d);
  return d[0] * scaled_vt[1] - d[1] * scaled_vt[0];
}

double slide_function(const Eigen::Matrix3d& a, const Eigen::Vector3d& q, double qn_b, double mu,
                      double phi) {
  return slide_function_cs(a, q, qn_b, mu, std::cos(phi), std::sin(phi));
}

bool same_solution(const Eigen::Vector3d& x, const Eigen::Vector3d& y, double scale) {
  return (x - y).norm() <= 1e-9 * scale;
}

// The sticking candidate p = -A^-1 (q + b e_n), when A is not singular (false otherwise).
// @p in_cone: p is inside the cone K_mu (with relative slack 1e-10). @p inverse: A^-1 if
// the caller has it (local_inverse() was true), else nullptr.
bool sticking_candidate(const Eigen::Matrix3d& a, const Eigen::Vector3d& q, double normal_bias,
                        double mu, const Eigen::Matrix3d* inverse, Eigen::Vector3d& p,
                        bool& in_cone) {
  Eigen::Matrix3d computed;
  if (inverse == nullptr) {
    if (!local_inverse(a, computed))
      return false;
    inverse = &computed;
  }
  Eigen::Vector3d rhs = q;
  rhs[0] += normal_bias;
  p = -(*inverse) * rhs;
  in_cone = p[0] > 0.0 && std::sqrt(p[1] * p[1] + p[2] * p[2]) <= mu * p[0] * (1.0 + 1e-10);
  return true;
}

// LocalSearch::first: the preferred solution without enumeration. Returns false when it
// cannot decide (no sticking or separation, and Newton on phi fails), leaving the scan to it.
bool solve_first(const Eigen::Matrix3d& a, const Eigen::Vector3d& q, double normal_bias, double mu,
                 const Eigen::Vector3d& previous, const Eigen::Matrix3d* inverse,
                 LocalSolution& out) {
  const double qn_b = q[0] + normal_bias;
  const double q_scale = std::max(std::abs(qn_b), q.tail<2>().norm());
  const double tol_velocity = 1e-12 * q_scale;
  if (qn_b >= -tol_velocity) {
    out.impulse.setZero();
    out.n_solutions = 1;
    out.kind = LocalSolution::Kind::separation;
    return true;
  }
  if (mu == 0.0) {
    if (!(a(0, 0) > 0.0))
      return false;
    const double pn = -qn_b / a(0, 0);
    if (!(pn > 0.0))
      return false;
    out.impulse = Eigen::Vector3d(pn, 0.0, 0.0);
    out.n_solutions = 1;
    out.kind = LocalSolution::Kind::sliding;
    return true;
  }
  Eigen::Vector2d direction = previous.tail<2>();
  Eigen::Vector3d p_stick;
  bool in_cone = false;
  if (sticking_candidate(a, q, normal_bias, mu, inverse, p_stick, in_cone)) {
    if (in_cone) {
      out.impulse = p_stick;
      out.n_solutions = 1;
      out.kind = LocalSolution::Kind::sticking;
      return true;
    }
    if (!(direction.squaredNorm() > 0.0))
      direction = p_stick.tail<2>();
  }
  if (!(direction.squaredNorm() > 0.0) || !direction.allFinite())
    return false;
  // Newton on f(phi) = d x w, w = den q_t - (q_n + b)(A_tn + mu A_tt d), d = (cos, sin):
  //   f' = -(d . w) + d x w',  w' = den' q_t - (q_n + b) mu A_tt d_perp,  den' = mu A_nt d_perp.
  const Eigen::Vector2d a_nt(a(0, 1), a(0, 2)), a_tn(a(1, 0), a(2, 0));
  const Eigen::Matrix2d a_tt = a.bottomRightCorner<2, 2>();
  double phi = std::atan2(direction[1], direction[0]);
  bool converged = false;
  for (int it = 0; it < 40; ++it) {
    const Eigen::Vector2d d(std::cos(phi), std::sin(phi)), d_perp(-d[1], d[0]);
    const double den = a(0, 0) + mu * a_nt.dot(d);
    const Eigen::Vector2d w = den * q.tail<2>() - qn_b * (a_tn + mu * a_tt * d);
    const Eigen::Vector2d w_prime =
        mu * a_nt.dot(d_perp) * q.tail<2>() - qn_b * mu * (a_tt * d_perp);
    const double f = d[0] * w[1] - d[1] * w[0];
    const double f_prime = -d.dot(w) + d[0] * w_prime[1] - d[1] * w_prime[0];
    if (f == 0.0) {
      converged = true;
      break;
    }
    if (!(f_prime != 0.0) || !std::isfinite(f_prime))
      return false;
    const double step = std::clamp(-f / f_prime, -0.5, 0.5);
    phi += step;
    if (std::abs(step) <= 1e-14 * (1.0 + std::abs(phi))) {
      converged = true;
      break;
    }
  }
  if (!converged)
    return false;
  const Eigen::Vector2d d(std::cos(phi), std::sin(phi));
  const double den = a(0, 0) + mu * a_nt.dot(d);
  if (den == 0.0)
    return false;
  const double pn = -qn_b / den;
  if (!(pn > 0.0))
    return false;
  const Eigen::Vector3d p(pn, mu * pn * d[0], mu * pn * d[1]);
  const Eigen::Vector3d v = a * p + q;
  // Valid: v_t opposes the friction direction and is parallel to it.
  const double along = v[1] * d[0] + v[2] * d[1];
  const double across = v[2] * d[0] - v[1] * d[1];
  if (!(along <= tol_velocity) || !(std::abs(across) <= 1e-9 * (q_scale + v.norm())))
    return false;
  out.impulse = p;
  out.n_solutions = 1;
  out.kind = LocalSolution::Kind::sliding;
  return true;
}

} // namespace

bool local_inverse(const Eigen::Matrix3d& a, Eigen::Matrix3d& inverse) {
  const double a_scale = a.diagonal().cwiseAbs().maxCoeff();
  if (!(a_scale > 0.0) || !(std::abs(a.determinant()) > 1e-13 * a_scale * a_scale * a_scale))
    return false;
  inverse = a.inverse();
  return true;
}

LocalSolution solve_local_contact(const Eigen::Matrix3d& a, const Eigen::Vector3d& q,
                                  double normal_bias, double mu, const Eigen::Vector3d& previous,
                                  LocalSearch search, const Eigen::Matrix3d* inverse) {
  LocalSolution out;
  if (search == LocalSearch::first && solve_first(a, q, normal_bias, mu, previous, inverse, out))
    return out;
  const double qn_b = q[0] + normal_bias;
  const double a_scale = a.diagonal().cwiseAbs().maxCoeff();
  const double q_scale = std::max(std::abs(qn_b), q.tail<2>().norm());
  // Tolerances on validity checks, relative to the data.
  const double tol_velocity = 1e-12 * q_scale;

  Eigen::Vector3d candidates[6];
  LocalSolution::Kind kinds[6];
  int n_candidates = 0;
  auto add = [&](const Eigen::Vector3d& p, LocalSolution::Kind kind) {
    const double p_scale = std::max(p.norm(), q_scale / std::max(a_scale, 1e-300));
    for (int i = 0; i < n_candidates; ++i)
      if (same_solution(candidates[i], p, p_scale))
        return;
    candidates[n_candidates] = p;
    kinds[n_candidates] = kind;
    ++n_candidates;
  };

  // Separation.
  if (qn_b >= -tol_velocity)
    add(Eigen::Vector3d::Zero(), LocalSolution::Kind::separation);

  // Sticking (mu > 0; mu = 0 is handled as frictionless sliding below).
  if (mu > 0.0) {
    Eigen::Vector3d p;
    bool in_cone = false;
    if (sticking_candidate(a, q, normal_bias, mu, inverse, p, in_cone) && in_cone)
      add(p, LocalSolution::Kind::sticking);
  }

  // Sliding.
  if (mu == 0.0) {
    if (a(0, 0) > 0.0) {
      const double pn = -qn_b / a(0, 0);
      if (pn > 0.0)
        add(Eigen::Vector3d(pn, 0.0, 0.0), LocalSolution::Kind::sliding);
    }
  } else {
    // Scan a 64-point grid (trigonometric values from a table), refine each
    // sign change by the Illinois variant of regula falsi.
    constexpr int n_grid = 64;
    static const GridTable table;
    const double step = 2.0 * kPi / n_grid;
    double f_lo = slide_function_cs(a, q, qn_b, mu, table.cos[0], table.sin[0]);
    for (int i = 1; i <= n_grid; ++i) {
      const double phi_lo = (i - 1) * step, phi_hi = i * step;
      const double f_hi =
          slide_function_cs(a, q, qn_b, mu, table.cos[i % n_grid], table.sin[i % n_grid]);
      double root = std::numeric_limits<double>::quiet_NaN();
      if (f_lo == 0.0) {
        root = phi_lo;
      } else if ((f_lo < 0.0) != (f_hi < 0.0) && f_hi != 0.0) {
        double lo = phi_lo, hi = phi_hi, flo = f_lo, fhi = f_hi;
        int side = 0;
        for (int it = 0; it < 100 && hi - lo > 1e-14; ++it) {
          const double mid = (lo * fhi - hi * flo) / (fhi - flo);
          const double fmid = slide_function(a, q, qn_b, mu, mid);
          if (fmid == 0.0) {
            lo = hi = mid;
            break;
          }
          if ((fmid < 0.0) == (flo < 0.0)) {
            lo = mid;
            flo = fmid;
            if (side == -1)
              fhi *= 0.5;
            side = -1;
          } else {
            hi = mid;
            fhi = fmid;
            if (side == 1)
              flo *= 0.5;
            side = 1;
          }
        }
        root = 0.5 * (lo + hi);
      }
      if (std::isfinite(root)) {
        const Eigen::Vector2d d(std::cos(root), std::sin(root));
        const double den = a(0, 0) + mu * (a(0, 1) * d[0] + a(0, 2) * d[1]);
        if (den != 0.0) {
          const double pn = -qn_b / den;
          if (pn > 0.0) {
            const Eigen::Vector3d p(pn, mu * pn * d[0], mu * pn * d[1]);
            const Eigen::Vector3d v = a * p + q;
            const double along = v[1] * d[0] + v[2] * d[1];
            // v_t must oppose the friction direction (alpha >= 0).
            if (along <= tol_velocity)
              add(p, LocalSolution::Kind::sliding);
          }
        }
      }
      f_lo = f_hi;
    }
  }

  out.n_solutions = n_candidates;
  if (n_candidates == 0)
    return out;
  int best = 0;
  for (int i = 1; i < n_candidates; ++i) {
    if (kinds[best] != kinds[i]) {
      if (static_cast<int>(kinds[i]) < static_cast<int>(kinds[best]))
        best = i;
    } else if ((candidates[i] - previous).norm() < (candidates[best] - previous).norm()) {
      best = i;
    }
  }
  out.impulse = candidates[best];
  out.kind = kinds[best];
  return out;
}

} // namespace plantar::contact
