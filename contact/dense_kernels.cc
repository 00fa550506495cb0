#include "contact/dense_kernels.h"

#include <cmath>
#include <cstring>

namespace plantar::contact {

// One load of each column element and one fused multiply-add: with AVX2/FMA about one read
// pass over the three columns; the baseline (SSE2) needs a multiply and an add per element.
// On x86-64 with GCC both versions are built and the loader picks one (ifunc, by CPU
// features: "arch=haswell" would test the CPU model and miss other AVX2 CPUs); elsewhere the
// compiler's own target.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PLANTAR_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define PLANTAR_KERNEL_CLONES
#endif

PLANTAR_KERNEL_CLONES void add_three_columns(const double* columns, Eigen::Index stride,
                                             Eigen::Index rows, const double* d, double* w) {
  const double d0 = d[0], d1 = d[1], d2 = d[2];
  const double* c0 = columns;
  const double* c1 = columns + stride;
  const double* c2 = columns + 2 * stride;
  for (Eigen::Index i = 0; i < rows; ++i) {
    w[i] += c0[i] * d0 + c1[i] * d1 + c2[i] * d2;
  }
}

PLANTAR_KERNEL_CLONES void solve_lower_three(const double* l, Eigen::Index stride, Eigen::Index n,
                                             double* b, Eigen::Index b_stride) {
  double* b0 = b;
  double* b1 = b + b_stride;
  double* b2 = b + 2 * b_stride;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* column = l + j * stride;
    const double inverse = 1.0 / column[j];
    const double x0 = b0[j] * inverse, x1 = b1[j] * inverse, x2 = b2[j] * inverse;
    b0[j] = x0;
    b1[j] = x1;
    b2[j] = x2;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      b0[i] -= column[i] * x0;
      b1[i] -= column[i] * x1;
      b2[i] -= column[i] * x2;
    }
  }
}

PLANTAR_KERNEL_CLONES void solve_lower(const double* l, Eigen::Index stride, Eigen::Index n,
                                       double* b) {
  Eigen::Index j = 0;
  for (; j + 4 <= n; j += 4) {
    const double* c0 = l + j * stride;
    const double* c1 = c0 + stride;
    const double* c2 = c1 + stride;
    const double* c3 = c2 + stride;
    const double x0 = b[j] / c0[j];
    const double x1 = (b[j + 1] - c0[j + 1] * x0) / c1[j + 1];
    const double x2 = (b[j + 2] - c0[j + 2] * x0 - c1[j + 2] * x1) / c2[j + 2];
    const double x3 = (b[j + 3] - c0[j + 3] * x0 - c1[j + 3] * x1 - c2[j + 3] * x2) / c3[j + 3];
    b[j] = x0;
    b[j + 1] = x1;
    b[j + 2] = x2;
    b[j + 3] = x3;
    for (Eigen::Index i = j + 4; i < n; ++i)
      b[i] -= c0[i] * x0 + c1[i] * x1 + c2[i] * x2 + c3[i] * x3;
  }
  for (; j < n; ++j) {
    const double* column = l + j * stride;
    const double x = b[j] / column[j];
    b[j] = x;
    for (Eigen::Index i = j + 1; i < n; ++i)
      b[i] -= column[i] * x;
  }
}

namespace {
// Four doubles as one vector (GCC/Clang vector extension; two SSE2 registers or one AVX2).
typedef double Lanes __attribute__((vector_size(32)));
// Unaligned load of x[0..3] (a macro: a function returning Lanes changes ABI without AVX).
#define PLANTAR_LOAD_LANES(v, x) std::memcpy(&(v), (x), sizeof(Lanes))
} // namespace

PLANTAR_KERNEL_CLONES void solve_lower_transposed(const double* l, Eigen::Index stride,
                                                  Eigen::Index n, double* b) {
  // The last n mod 4 unknowns one by one, then blocks of four upwards. The dot products keep
  // four partial sums each (lanes), added in a fixed order.
  Eigen::Index i = n - 1;
  for (; i >= 0 && (i + 1) % 4 != 0; --i) {
    const double* column = l + i * stride;
    double s = b[i];
    for (Eigen::Index t = i + 1; t < n; ++t)
      s -= column[t] * b[t];
    b[i] = s / column[i];
  }
  for (; i >= 3; i -= 4) {
    const Eigen::Index j = i - 3; // columns j..j+3; x known from j + 4 on
    const double* c0 = l + j * stride;
    const double* c1 = c0 + stride;
    const double* c2 = c1 + stride;
    const double* c3 = c2 + stride;
    Lanes s0 = {0, 0, 0, 0}, s1 = s0, s2 = s0, s3 = s0;
    Eigen::Index t = j + 4;
    for (; t + 4 <= n; t += 4) {
      Lanes x, l0, l1, l2, l3;
      PLANTAR_LOAD_LANES(x, b + t);
      PLANTAR_LOAD_LANES(l0, c0 + t);
      PLANTAR_LOAD_LANES(l1, c1 + t);
      PLANTAR_LOAD_LANES(l2, c2 + t);
      PLANTAR_LOAD_LANES(l3, c3 + t);
      s0 += l0 * x;
      s1 += l1 * x;
      s2 += l2 * x;
      s3 += l3 * x;
    }
    for (; t < n; ++t) {
      s0[0] += c0[t] * b[t];
      s1[0] += c1[t] * b[t];
      s2[0] += c2[t] * b[t];
      s3[0] += c3[t] * b[t];
    }
    const double d0 = (s0[0] + s0[1]) + (s0[2] + s0[3]);
    const double d1 = (s1[0] + s1[1]) + (s1[2] + s1[3]);
    const double d2 = (s2[0] + s2[1]) + (s2[2] + s2[3]);
    const double d3 = (s3[0] + s3[1]) + (s3[2] + s3[3]);
    const double x3 = (b[j + 3] - d3) / c3[j + 3];
    const double x2 = (b[j + 2] - d2 - c2[j + 3] * x3) / c2[j + 2];
    const double x1 = (b[j + 1] - d1 - c1[j + 2] * x2 - c1[j + 3] * x3) / c1[j + 1];
    const double x0 = (b[j] - d0 - c0[j + 1] * x1 - c0[j + 2] * x2 - c0[j + 3] * x3) / c0[j];
    b[j] = x0;
    b[j + 1] = x1;
    b[j + 2] = x2;
    b[j + 3] = x3;
  }
}
#undef PLANTAR_LOAD_LANES

// The cases of project_onto_cone as selects, not branches (the case changes from contact to
// contact); the file is built with -fno-math-errno -fno-trapping-math, so they vectorise.
PLANTAR_KERNEL_CLONES double contact_residuals(Eigen::Index n, const double* p, const double* v,
                                               const double* bias, const double* mu,
                                               const double* eta, double* r) {
  for (Eigen::Index k = 0; k < n; ++k) {
    const double p0 = p[3 * k], p1 = p[3 * k + 1], p2 = p[3 * k + 2];
    const double v1 = v[3 * k + 1], v2 = v[3 * k + 2];
    const double m = mu[k], e = eta[k];
    const double s0 = v[3 * k] + bias[k] + m * std::sqrt(v1 * v1 + v2 * v2);
    const double x0 = p0 - e * s0, x1 = p1 - e * v1, x2 = p2 - e * v2;
    const double tangent = std::sqrt(x1 * x1 + x2 * x2);
    const bool inside = tangent <= m * x0;
    const bool polar = m * tangent <= -x0;
    const double scale = (x0 + m * tangent) / (1.0 + m * m);
    const double ratio = m * scale / (tangent > 0.0 ? tangent : 1.0);
    // polar first: inside and polar both hold only for x = 0 or (mu = 0, x_t = 0, x_n < 0),
    // where the projection is 0.
    const double q0 = polar ? 0.0 : (inside ? x0 : scale);
    const double q1 = polar ? 0.0 : (inside ? x1 : ratio * x1);
    const double q2 = polar ? 0.0 : (inside ? x2 : ratio * x2);
    const double d0 = p0 - q0, d1 = p1 - q1, d2 = p2 - q2;
    r[k] = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2) / e;
  }
  double worst = 0.0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (!(r[k] <= worst) && worst == worst) // takes a NaN r_k and keeps it
      worst = r[k];
  return worst;
}

} // namespace plantar::contact
