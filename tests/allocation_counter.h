#pragma once
// Counts the heap allocations of a test executable while `counting` is set. Include this header
// in exactly one file of the executable.
//
// Normal builds replace the global operator new / delete (every form), so operator new is
// counted (std containers; not Eigen's malloc). Under AddressSanitizer (CMake option
// PLANTAR_SANITIZE) a replacement would fight ASan's own allocator, so ASan's allocation hook
// counts instead: every malloc and operator new.

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace plantar::testing {
inline std::atomic<bool> counting{false};
inline std::atomic<long> n_allocations{0};
} // namespace plantar::testing

namespace plantar::testing {
/// The heap allocations counted while @p work runs (`during`), and whether the counter sees a
/// deliberate allocation made right after (`counter_works`: a test of "no allocation" must
/// assert it, else it cannot fail).
struct AllocationCount {
  long during = 0;
  bool counter_works = false;
};
template <class Work> AllocationCount count_allocations(Work&& work) {
  n_allocations = 0;
  counting = true;
  work();
  counting = false;
  AllocationCount result;
  result.during = n_allocations.load();
  counting = true;
  ::operator delete(::operator new(16)); // a call, not a new-expression: not elided
  counting = false;
  result.counter_works = n_allocations.load() > result.during;
  return result;
}
} // namespace plantar::testing

#if defined(__SANITIZE_ADDRESS__)

extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*,
                                                                             std::size_t),
                                                         void (*free_hook)(const volatile void*));

namespace plantar::testing {
inline void count_allocation(const volatile void*, std::size_t) {
  if (counting.load(std::memory_order_relaxed))
    n_allocations.fetch_add(1, std::memory_order_relaxed);
}
inline void ignore_free(const volatile void*) {}
inline const int allocation_hook_installed =
    __sanitizer_install_malloc_and_free_hooks(count_allocation, ignore_free);
} // namespace plantar::testing

#else

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
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return operator new(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return operator new(size, std::nothrow);
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
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

#endif
