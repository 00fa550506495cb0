#pragma once
// Counts every operator new of a test executable while `counting` is set: a global replacement
// of operator new / delete, so include this header in exactly one file of the executable.

#include <atomic>
#include <cstdlib>
#include <new>

namespace plantar::testing {
inline std::atomic<bool> counting{false};
inline std::atomic<long> n_allocations{0};
} // namespace plantar::testing

// The replacements pair malloc with free; GCC cannot see that and warns.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

void* operator new(std::size_t size) {
  if (plantar::testing::counting.load())
    ++plantar::testing::n_allocations;
  if (void* p = std::malloc(size ? size : 1))
    return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
