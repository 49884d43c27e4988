// Proof that LaneSolver::solve() never touches the heap after construction: every global
// operator new is replaced by a counting one, and malloc & co. are wrapped at link time
// (-Wl,--wrap, see CMakeLists.txt) so that Eigen's own allocations (std::malloc, inlined
// into the solver's objects) are counted too. Any allocation while counting fails.
#include <atomic>
#include <cstdlib>
#include <new>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "core/solver/lane_solver.hpp"
#include "tests/core/solver/synthetic_scene.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

void note_allocation() {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
}

void* counted_new(std::size_t size) {
  note_allocation();
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}

void* counted_aligned_new(std::size_t size, std::align_val_t align) {
  note_allocation();
  const std::size_t a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}

// Counts the allocations made while it is alive.
class AllocationCounter {
 public:
  AllocationCounter() {
    g_allocations = 0;
    g_counting = true;
  }
  ~AllocationCounter() { g_counting = false; }
  long count() const { return g_allocations.load(); }
};
}  // namespace

void* operator new(std::size_t size) { return counted_new(size); }
void* operator new[](std::size_t size) { return counted_new(size); }
void* operator new(std::size_t size, std::align_val_t a) { return counted_aligned_new(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return counted_aligned_new(size, a); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  note_allocation();
  return std::malloc(size ? size : 1);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  note_allocation();
  return std::malloc(size ? size : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

// The C allocator, as seen by this program's own objects and static libraries.
extern "C" {
void* __real_malloc(std::size_t);
void* __real_calloc(std::size_t, std::size_t);
void* __real_realloc(void*, std::size_t);
int __real_posix_memalign(void**, std::size_t, std::size_t);
void* __real_aligned_alloc(std::size_t, std::size_t);
void* __wrap_malloc(std::size_t n) {
  note_allocation();
  return __real_malloc(n);
}
void* __wrap_calloc(std::size_t n, std::size_t size) {
  note_allocation();
  return __real_calloc(n, size);
}
void* __wrap_realloc(void* p, std::size_t n) {
  note_allocation();
  return __real_realloc(p, n);
}
int __wrap_posix_memalign(void** p, std::size_t align, std::size_t n) {
  note_allocation();
  return __real_posix_memalign(p, align, n);
}
void* __wrap_aligned_alloc(std::size_t align, std::size_t n) {
  note_allocation();
  return __real_aligned_alloc(align, n);
}
}

namespace ccdlane {
namespace {

TEST(LaneSolverAllocation, CounterSeesNewAndEigenHeapAllocations) {
  // The proof below is only as good as the counter: show it catches both kinds.
  {
    AllocationCounter counter;
    auto* p = new double(1.0);
    EXPECT_GE(counter.count(), 1);
    delete p;
  }
  {
    AllocationCounter counter;
    Eigen::VectorXd v = Eigen::VectorXd::Ones(64);  // Eigen's aligned_malloc -> std::malloc
    EXPECT_GE(counter.count(), 1) << v.sum();
  }
}

FreeSet all_free() {
  FreeSet s;
  for (int p = 0; p < kFreeParamCount; ++p) s.add(static_cast<FreeParam>(p));
  return s;
}

TEST(LaneSolverAllocation, SolveNeverAllocatesAfterWarmUp) {
  std::mt19937_64 rng(7);
  test::SceneOptions options;
  options.num_lines = 3;
  options.num_picks = 60;
  options.max_slope = 0.01;
  options.max_curvature = 5e-7;
  const test::SyntheticScene scene = test::make_scene(rng, options);
  const std::vector<Pick> picks = test::noisy_picks(scene, 0.5, rng);
  std::vector<Pick> bad = picks;
  bad[4].px = std::nan("");
  const std::vector<LaneLine> lines = scene.lines;

  // Requests covering both modes, every parameter kind, all priors, a rank-deficient
  // problem, warm starts and rejected input.
  std::vector<SolveRequest> requests;
  SolveRequest base;
  base.initial_pose = scene.truth;
  base.picks = picks;
  base.num_lines = options.num_lines;
  base.initial_lines = lines;
  SolveRequest r = base;
  r.priors.theta_deg = Prior{0.0, 0.5};
  r.priors.phi_deg = Prior{0.0, 0.5};
  requests.push_back(r);  // default free set, gyro priors
  r = base;
  r.free = all_free();
  r.priors = {Prior{0, 1}, Prior{0, 1}, Prior{0, 1}, Prior{1400, 20}, Prior{5.05, 0.05}, Prior{3500, 150}};
  requests.push_back(r);  // everything free, every prior
  r = base;
  r.initial_lines = {};
  requests.push_back(r);  // rank-deficient (free roll and offsets), cold lines
  r = base;
  r.mode = SolverMode::paper;
  r.free.remove(FreeParam::phi);
  requests.push_back(r);
  r.free.add(FreeParam::c);
  requests.push_back(r);  // paper mode, curved lines: Newton for x_i
  r = base;
  r.picks = bad;
  requests.push_back(r);  // invalid input
  r = base;
  r.picks = std::span<const Pick>(picks).first(2);
  requests.push_back(r);  // too few picks

  LaneSolver solver(scene.camera, 64, kMaxLaneLines);
  for (const SolveRequest& req : requests) solver.solve(req);  // warm-up (nothing lazy expected)
  AllocationCounter counter;
  int converged = 0;
  for (int round = 0; round < 2; ++round)
    for (const SolveRequest& req : requests) converged += solver.solve(req).converged;
  const long allocations = counter.count();
  EXPECT_EQ(allocations, 0);
  EXPECT_GE(converged, 2 * 5);  // the solves above really ran
}

}  // namespace
}  // namespace ccdlane
