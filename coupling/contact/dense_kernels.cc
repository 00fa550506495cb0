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

} // namespace plantar::coupling
