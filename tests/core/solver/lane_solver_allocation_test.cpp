// Proof that LaneSolver::solve() never touches the heap after construction: operator new
// and, through the link-time wrap of ccdlane_malloc_counter, malloc & co. (where Eigen's
// allocations land, inlined into the solver's objects) are counted. Any allocation while
// counting fails.
#include <cmath>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "core/solver/lane_solver.hpp"
#include "tests/core/solver/synthetic_scene.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

TEST(LaneSolverAllocation, CounterSeesNewAndEigenHeapAllocations) {
  // The proof below is only as good as the counter: show it catches both kinds.
  {
    test::AllocationScope counter;
    auto* p = new double(1.0);
    EXPECT_GE(counter.count(), 1u);
    delete p;
  }
  {
    test::AllocationScope counter;
    Eigen::VectorXd v = Eigen::VectorXd::Ones(64);  // Eigen's aligned_malloc -> std::malloc
    EXPECT_GE(counter.count(), 1u) << v.sum();
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
  const std::vector<RoadLine> lines = scene.lines;

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
  r.free.remove(FreeParam::c);
  r.line_model = LineModel::shared_curvature;
  requests.push_back(r);  // paper mode, one curvature for all lines
  r = base;
  r.priors.phi_deg = Prior{0.0, 0.5};
  r.line_model = LineModel::shared_curvature;
  requests.push_back(r);  // a bend: one curvature for all lines
  r = base;
  r.picks = bad;
  requests.push_back(r);  // invalid input
  r = base;
  r.picks = std::span<const Pick>(picks).first(2);
  requests.push_back(r);  // too few picks

  LaneSolver solver(scene.camera, 64, kMaxLaneLines);
  for (const SolveRequest& req : requests) solver.solve(req);  // warm-up (nothing lazy expected)
  test::AllocationScope counter;
  int converged = 0;
  for (int round = 0; round < 2; ++round)
    for (const SolveRequest& req : requests) converged += solver.solve(req).converged;
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GE(converged, 2 * 7);  // the solves above really ran
}

}  // namespace
}  // namespace ccdlane
