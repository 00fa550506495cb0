#include "coupling/contact/dense_kernels.h"

namespace plantar::coupling {

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

// Per column j of the triangle: an axpy below the diagonal and a dot product (four partial
// sums) for row j, for each of the three columns of B.
PLANTAR_KERNEL_CLONES void symmetric_lower_times_three(const double* h, Eigen::Index stride,
                                                       Eigen::Index n, const double* b,
                                                       Eigen::Index b_stride, double* u,
                                                       Eigen::Index u_stride) {
  for (int r = 0; r < 3; ++r)
    for (Eigen::Index i = 0; i < n; ++i)
      u[r * u_stride + i] = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* __restrict column = h + j * stride;
    for (int r = 0; r < 3; ++r) {
      const double* __restrict br = b + r * b_stride;
      double* __restrict ur = u + r * u_stride;
      const double bj = br[j];
      double t0 = 0.0, t1 = 0.0, t2 = 0.0, t3 = 0.0;
      Eigen::Index i = j + 1;
      for (; i + 4 <= n; i += 4) {
        ur[i] += column[i] * bj;
        ur[i + 1] += column[i + 1] * bj;
        ur[i + 2] += column[i + 2] * bj;
        ur[i + 3] += column[i + 3] * bj;
        t0 += column[i] * br[i];
        t1 += column[i + 1] * br[i + 1];
        t2 += column[i + 2] * br[i + 2];
        t3 += column[i + 3] * br[i + 3];
      }
      for (; i < n; ++i) {
        ur[i] += column[i] * bj;
        t0 += column[i] * br[i];
      }
      ur[j] += column[j] * bj + ((t0 + t1) + (t2 + t3));
    }
  }
}

} // namespace plantar::coupling
