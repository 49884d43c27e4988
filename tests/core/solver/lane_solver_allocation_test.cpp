// Proof that LaneSolver::solve() never touches the heap after construction. Operator
// new is counted by the shared tests/support/allocation_counter; Eigen allocates with
// std::malloc (inlined into the solver's own objects), so malloc & co. are also wrapped
// at link time here (-Wl,--wrap, see CMakeLists.txt), which works under the sanitizers
// too. Any allocation while counting fails.
#include <atomic>
#include <cmath>
#include <cstdlib>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "core/solver/lane_solver.hpp"
#include "tests/core/solver/synthetic_scene.hpp"
#include "tests/support/allocation_counter.hpp"

namespace {
std::atomic<long> g_mallocs{0};
}  // namespace

// The C allocator, as seen by this program's own objects and static libraries.
extern "C" {
void* __real_malloc(std::size_t);
void* __real_calloc(std::size_t, std::size_t);
void* __real_realloc(void*, std::size_t);
int __real_posix_memalign(void**, std::size_t, std::size_t);
void* __real_aligned_alloc(std::size_t, std::size_t);
void* __wrap_malloc(std::size_t n) {
  ++g_mallocs;
  return __real_malloc(n);
}
void* __wrap_calloc(std::size_t n, std::size_t size) {
  ++g_mallocs;
  return __real_calloc(n, size);
}
void* __wrap_realloc(void* p, std::size_t n) {
  ++g_mallocs;
  return __real_realloc(p, n);
}
int __wrap_posix_memalign(void** p, std::size_t align, std::size_t n) {
  ++g_mallocs;
  return __real_posix_memalign(p, align, n);
}
void* __wrap_aligned_alloc(std::size_t align, std::size_t n) {
  ++g_mallocs;
  return __real_aligned_alloc(align, n);
}
}

namespace {
// Heap allocations of either kind made while it is alive (the test is single-threaded).
class AllocationCounter {
 public:
  AllocationCounter() : mallocs_(g_mallocs.load()) {}
  long count() const { return static_cast<long>(news_.count()) + (g_mallocs.load() - mallocs_); }

 private:
  ccdlane::test::AllocationScope news_;
  long mallocs_;
};
}  // namespace

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
  base.warm_start = true;
  SolveRequest r = base;
  r.priors.theta_deg = Prior{0.0, 0.5};
  r.priors.phi_deg = Prior{0.0, 0.5};
  requests.push_back(r);  // default free set, gyro priors
  r = base;
  r.free = test::all_free();
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
