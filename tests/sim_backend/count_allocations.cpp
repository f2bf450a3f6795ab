// Counts heap allocations in this test program, so the real-time claims of the core tick and of
// the plant's arm are tested, not assumed (as tests/control does for the module).
#include <atomic>
#include <cstdlib>
#include <new>

// GCC cannot see that these replacements pair malloc with free.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
namespace {
std::atomic<long> g_allocations{0};
}  // namespace
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
namespace mg::testing {
long allocations() { return g_allocations.load(); }
}  // namespace mg::testing
