// ReprojectionResidual: residuals are the whitened pixel errors of the picks' road
// points, and every analytic Jacobian column matches central finite differences.
#include "core/solver/reprojection_residual.hpp"

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/solver/parameter_layout.hpp"
#include "tests/core/solver/jacobian_check.hpp"
#include "tests/core/solver/synthetic_scene.hpp"

namespace ccdlane::solver {
namespace {

struct Fixture {
  test::SyntheticScene scene;  // its picks sorted by line, as the solver keeps them
  LineSegments segments;
  std::vector<double> x;
  PickRows rows{16};
  ParameterLayout layout{test::all_free(), 2};
  SolverPriors priors;
  SolverState state;

  explicit Fixture(std::uint64_t seed, const ParameterLayout& with_layout = ParameterLayout(test::all_free(), 2))
      : layout(with_layout) {
    scene = test::small_curved_scene(seed);
    std::vector<std::size_t> order(scene.picks.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return scene.picks[a].line < scene.picks[b].line; });
    const test::SyntheticScene interleaved = scene;
    for (std::size_t i = 0; i < order.size(); ++i) {
      scene.picks[i] = interleaved.picks[order[i]];
      scene.x_mm[i] = interleaved.x_mm[order[i]];
      segments.begin[scene.picks[i].line + 1] = static_cast<int>(i) + 1;
    }
    x = scene.x_mm;
    for (double& xi : x) xi *= 1.01;  // off the truth: residuals are not zero
    state.pose = scene.truth;
    std::copy(scene.lines.begin(), scene.lines.end(), state.lines.begin());
    state.lines[1].c_per_mm += 3e-7;
    state.x = x.data();
    state.rows = &rows;
  }
};

TEST(ReprojectionResidual, ResidualsAreWhitenedPixelErrors) {
  Fixture f(1);
  ReprojectionResidual model(f.scene.camera, 16);
  model.configure(f.layout, f.segments, f.scene.picks, 0.5, f.priors);
  ASSERT_TRUE(model.evaluate(f.state));
  const CameraModel camera(f.scene.camera, f.state.pose);
  double cost = 0.0;
  for (std::size_t i = 0; i < f.x.size(); ++i) {
    const Pick& p = f.scene.picks[i];
    const RoadLine& l = f.state.lines[p.line];
    const Vec2 px = *camera.pixel_from_point(Vec3(f.x[i], l.y0_mm + l.m * f.x[i] + l.c_per_mm * f.x[i] * f.x[i], 0));
    const Vec2 r = (px - Vec2(p.px, p.py)) / 0.5;
    EXPECT_NEAR(f.rows.r0[i], r.x(), 1e-9);
    EXPECT_NEAR(f.rows.r1[i], r.y(), 1e-9);
    cost += r.squaredNorm();
  }
  EXPECT_NEAR(f.state.cost, cost, 1e-9 * cost);
}

// Everything free with a curvature per line, and with one curvature shared by the lines.
ParameterLayout layout_of_case(std::uint64_t seed) {
  FreeSet all_but_c = test::all_free();
  all_but_c.remove(FreeParam::c);
  return seed % 2 ? ParameterLayout(test::all_free(), 2) : ParameterLayout(all_but_c, 2, LineModel::shared_curvature);
}

TEST(ReprojectionResidual, JacobiansMatchFiniteDifferences) {
  for (std::uint64_t seed = 2; seed < 8; ++seed) {
    Fixture f(seed, layout_of_case(seed));
    ReprojectionResidual model(f.scene.camera, 16);
    model.configure(f.layout, f.segments, f.scene.picks, 0.5, f.priors);
    ASSERT_TRUE(model.evaluate(f.state));
    const PickRows analytic = f.rows;
    const SolverState base = f.state;
    const std::vector<double> x0 = f.x;
    const auto residuals_at = [&](const ReducedVector& step, int pick_moved, double dx) {
      SolverState s = base;
      std::vector<double> x = x0;
      if (pick_moved >= 0) x[pick_moved] += dx;
      s.x = x.data();
      PickRows b(static_cast<int>(x.size()));
      s.rows = &b;
      f.layout.apply_step(step, s.pose, s.lines.data());
      EXPECT_TRUE(model.evaluate(s));
      Eigen::VectorXd r(2 * x.size());
      for (std::size_t i = 0; i < x.size(); ++i) r.segment<2>(2 * i) = b.residual(static_cast<int>(i));
      return r;
    };
    const int n = f.layout.size();
    // Steps sized to each unknown's scale: radians, mm, slope, 1/mm.
    const auto step_size = [&](int k) {
      switch (f.layout.describe(k).kind) {
        case FreeParam::H:
        case FreeParam::y0: return 1e-3;
        case FreeParam::f: return 1e-6;
        case FreeParam::c: return 1e-11;
        default: return 1e-7;
      }
    };
    for (int k = 0; k < n; ++k) {
      const double h = step_size(k);
      const Eigen::VectorXd fd = test::central_difference(
          [&](double t) {
            ReducedVector step = ReducedVector::Zero(n);
            step[k] = t;
            return residuals_at(step, -1, 0.0);
          },
          h);
      const ReducedParam p = f.layout.describe(k);
      for (std::size_t i = 0; i < x0.size(); ++i) {
        const int line = f.scene.picks[i].line;
        // Column of parameter k in pick i's local block (0 if it is another line's).
        double col[2] = {0, 0};
        if (p.line < 0 || p.line == line) {
          const int local = p.line < 0 ? k : f.layout.num_global() + (k - f.layout.line_offset(line));
          col[0] = analytic.jacobian_column(static_cast<int>(i), local)[0];
          col[1] = analytic.jacobian_column(static_cast<int>(i), local)[1];
        }
        for (int c = 0; c < 2; ++c)
          EXPECT_NEAR(col[c], fd[2 * i + c], 1e-5 * (1.0 + std::abs(fd[2 * i + c]))) << "param " << k << " pick " << i;
      }
    }
    for (std::size_t i = 0; i < x0.size(); ++i) {
      const Eigen::VectorXd fd = test::central_difference(
          [&](double t) { return residuals_at(ReducedVector::Zero(n), static_cast<int>(i), t); }, 1e-3);
      EXPECT_NEAR(analytic.jx0[i], fd[2 * i], 1e-7 * (1.0 + std::abs(fd[2 * i])));
      EXPECT_NEAR(analytic.jx1[i], fd[2 * i + 1], 1e-7 * (1.0 + std::abs(fd[2 * i + 1])));
    }
  }
}

TEST(ReprojectionResidual, PointBehindTheCameraFailsTheEvaluation) {
  Fixture f(7);
  f.x[3] = -5000.0;
  ReprojectionResidual model(f.scene.camera, 16);
  model.configure(f.layout, f.segments, f.scene.picks, 0.5, f.priors);
  EXPECT_FALSE(model.evaluate(f.state));
}

}  // namespace
}  // namespace ccdlane::solver
