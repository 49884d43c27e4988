// PaperResidual: the residuals are docs/solver.md's r1, r2 written out literally, each x_i is
// the minimiser of r1^2 + r2^2, and the Jacobians match finite differences at fixed x.
#include "core/solver/paper_residual.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tests/core/solver/jacobian_check.hpp"
#include "tests/core/solver/synthetic_scene.hpp"

namespace ccdlane::solver {
namespace {

// docs/solver.md's r1, r2 for one pick at distance x on `line`, at `pose`.
Vec2 spec_residuals(const CameraSpec& spec, const CameraPose& pose, const Vec2& ideal, const RoadLine& line, double x) {
  const CameraModel cam(spec, pose);
  const Vec3 L = cam.lens_centre(), P = cam.cell_centre(ideal);
  const double y = line.y0_mm + line.m * x + line.c_per_mm * x * x;
  return {(x - L.x()) * (P.y() - L.y()) - (y - L.y()) * (P.x() - L.x()),
          (x - L.x()) * (P.z() - L.z()) + L.z() * (P.x() - L.x())};
}

TEST(PaperOptimalX, MinimisesTheSumOfSquaresWithAndWithoutCurvature) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const double a1 = 100 * u(rng), b1 = 1e5 * u(rng), a2 = 50 + 100 * std::abs(u(rng)), b2 = 1e6 * u(rng);
    const double q = trial % 2 ? 1e-4 * u(rng) : 0.0;
    const auto f = [&](double x) {
      const double r1 = (a1 - q * x) * x + b1, r2 = a2 * x + b2;
      return r1 * r1 + r2 * r2;
    };
    const double x = paper_optimal_x(a1, b1, q, a2, b2);
    // Stationary, and no better than its neighbours at a relative 1e-6.
    const double h = 1e-6 * std::max(1.0, std::abs(x));
    EXPECT_LE(f(x), f(x + h) * (1 + 1e-12)) << trial;
    EXPECT_LE(f(x), f(x - h) * (1 + 1e-12)) << trial;
  }
}

struct Fixture {
  test::SyntheticScene scene;
  std::vector<Vec2> ideal;
  std::vector<double> x;
  PickRows rows{16};
  ParameterLayout layout;
  SolverState state;

  explicit Fixture(std::uint64_t seed) {
    layout = ParameterLayout(test::all_free(), 2);
    scene = test::small_curved_scene(seed);
    const CameraModel cam(scene.camera, scene.truth);
    for (const Pick& p : scene.picks) ideal.push_back(*cam.ideal_from_observed(Vec2(p.px, p.py)));
    x.assign(scene.picks.size(), 0.0);
    state.pose = scene.truth;
    state.pose.attitude.psi += 0.01;  // off the truth: residuals are not zero
    std::copy(scene.lines.begin(), scene.lines.end(), state.lines.begin());
    state.x = x.data();
    state.rows = &rows;
  }
};

TEST(PaperResidual, ResidualsAreTheSpecificationsAtTheOptimalX) {
  Fixture f(1);
  PaperResidual model(f.scene.camera);
  model.configure(f.layout, f.scene.picks, f.ideal);
  ASSERT_TRUE(model.evaluate(f.state));
  for (std::size_t i = 0; i < f.x.size(); ++i) {
    const RoadLine& line = f.state.lines[f.scene.picks[i].line];
    const Vec2 r = spec_residuals(f.scene.camera, f.state.pose, f.ideal[i], line, f.x[i]);
    EXPECT_NEAR(f.rows.r0[i], r.x(), 1e-9 * r.norm() + 1e-6);
    EXPECT_NEAR(f.rows.r1[i], r.y(), 1e-9 * r.norm() + 1e-6);
    // No other x does better.
    for (const double dx : {-1.0, 1.0}) {
      const Vec2 other = spec_residuals(f.scene.camera, f.state.pose, f.ideal[i], line, f.x[i] + dx);
      EXPECT_GE(other.squaredNorm(), r.squaredNorm() * (1 - 1e-12));
    }
  }
  // At the truth (straight or curved, exact picks) every residual vanishes.
  f.state.pose = f.scene.truth;
  ASSERT_TRUE(model.evaluate(f.state));
  EXPECT_LT(f.state.cost, 1e-9);
  for (std::size_t i = 0; i < f.x.size(); ++i) EXPECT_NEAR(f.x[i], f.scene.x_mm[i], 1e-6 * f.scene.x_mm[i]);
}

TEST(PaperResidual, JacobiansMatchFiniteDifferencesAtFixedX) {
  FreeSet all_but_c = test::all_free();
  all_but_c.remove(FreeParam::c);
  // A curvature per line, and one shared by the lines.
  for (const ParameterLayout& layout :
       {ParameterLayout(test::all_free(), 2), ParameterLayout(all_but_c, 2, LineModel::shared_curvature)}) {
    Fixture f(2);
    f.layout = layout;
    PaperResidual model(f.scene.camera);
    model.configure(f.layout, f.scene.picks, f.ideal);
    ASSERT_TRUE(model.evaluate(f.state));
    const int n = f.layout.size();
    for (std::size_t i = 0; i < f.x.size(); ++i) {
      const int line = f.scene.picks[i].line;
      const auto r_at = [&](const ReducedVector& step, double dx) {
        CameraPose pose = f.state.pose;
        std::array<RoadLine, kMaxLaneLines> lines = f.state.lines;
        f.layout.apply_step(step, pose, lines.data());
        const Vec2 r = spec_residuals(f.scene.camera, pose, f.ideal[i], lines[line], f.x[i] + dx);
        return Eigen::VectorXd(r);
      };
      for (int k = 0; k < n; ++k) {
        const ReducedParam p = f.layout.describe(k);
        if (p.line >= 0 && p.line != line) continue;
        // Residuals are ~1e7 mm^2: steps large enough that rounding (1e-16 r / h) stays small.
        double h = 1e-5;  // radians
        if (p.kind == FreeParam::H || p.kind == FreeParam::y0) h = 1e-2;
        if (p.kind == FreeParam::f) h = 1e-3;
        if (p.kind == FreeParam::m) h = 1e-7;
        if (p.kind == FreeParam::c) h = 1e-11;
        const Eigen::VectorXd fd = test::central_difference(
            [&](double t) {
              ReducedVector step = ReducedVector::Zero(n);
              step[k] = t;
              return r_at(step, 0.0);
            },
            h);
        const int local = p.line < 0 ? k : f.layout.num_global() + (k - f.layout.line_offset(line));
        for (int c = 0; c < 2; ++c)
          EXPECT_NEAR(f.rows.jacobian_column(static_cast<int>(i), local)[c], fd[c], 1e-6 * (std::abs(fd[c]) + 1e3))
              << "param " << k << " pick " << i;
      }
      const Eigen::VectorXd fd =
          test::central_difference([&](double t) { return r_at(ReducedVector::Zero(n), t); }, 1e-3);
      EXPECT_NEAR(f.rows.jx0[i], fd[0], 1e-6 * (std::abs(fd[0]) + 1.0));
      EXPECT_NEAR(f.rows.jx1[i], fd[1], 1e-6 * (std::abs(fd[1]) + 1.0));
    }
  }
}

}  // namespace
}  // namespace ccdlane::solver
