// Force-included (-include) in every translation unit of walking_no_malloc: Eigen reports any
// heap allocation made while Eigen::internal::set_is_malloc_allowed(false) is in effect, also in
// Release builds (eigen_assert throws instead of being compiled out).
#pragma once
#include <stdexcept>
#define EIGEN_RUNTIME_NO_MALLOC
#define eigen_assert(x)                                                                            \
  do {                                                                                             \
    if (!(x))                                                                                      \
      throw std::runtime_error("Eigen assertion failed: " #x);                                     \
  } while (false)
