// Prior rows: whitened residuals in configured units, their derivatives, and the lane
// width taken between the outermost lines.
#include "core/solver/prior_residuals.hpp"

#include <gtest/gtest.h>

#include "tests/core/solver/synthetic_scene.hpp"

namespace ccdlane::solver {
namespace {

using test::free_set;

TEST(PriorResiduals, AnglesInDegreesLengthsInMillimetres) {
  using enum FreeParam;
  const ParameterLayout layout(free_set({theta, phi, H, y0}), 2);
  SolverPriors priors;
  priors.phi_deg = Prior{1.0, 0.5};
  priors.H_mm = Prior{1400.0, 20.0};
  priors.psi_deg = Prior{0.0, 2.0};  // psi is fixed: constant residual, no derivative
  const CameraPose pose{{deg_to_rad(3.0), 0.0, deg_to_rad(2.0)}, 1430.0, 5.05};
  const RoadLine lines[2] = {{1700.0, 0, 0}, {-1800.0, 0, 0}};
  PriorRows rows;
  double cost = 0.0;
  evaluate_priors(priors, layout, pose, lines, rows, cost);
  ASSERT_EQ(rows.count, 3);
  EXPECT_NEAR(rows.rows[0].r, 1.5, 1e-12);  // psi: (3 - 0) / 2
  EXPECT_EQ(rows.rows[0].size, 0);
  EXPECT_NEAR(rows.rows[1].r, 2.0, 1e-12);  // phi: (2 - 1) / 0.5
  EXPECT_NEAR(rows.rows[1].at(layout.global_index(kPhi)), rad_to_deg(1.0) / 0.5, 1e-9);
  EXPECT_NEAR(rows.rows[2].r, 1.5, 1e-12);  // H: (1430 - 1400) / 20
  EXPECT_NEAR(rows.rows[2].at(layout.global_index(kHeight)), 1.0 / 20.0, 1e-15);
  EXPECT_NEAR(cost, 1.5 * 1.5 + 2.0 * 2.0 + 1.5 * 1.5, 1e-12);
  EXPECT_EQ(count_free_priors(priors, layout), 2);
}

// The one lane-width row: residual r, +1/sigma on line `left`'s y0, -1/sigma on `right`'s,
// nothing on `other`'s.
void expect_width_row(const PriorRows& rows, const ParameterLayout& layout, double r, double sigma, int left,
                      int right, int other) {
  ASSERT_EQ(rows.count, 1);
  EXPECT_NEAR(rows.rows[0].r, r, 1e-12);
  EXPECT_NEAR(rows.rows[0].at(layout.line_index(left, kY0)), 1.0 / sigma, 1e-15);
  EXPECT_NEAR(rows.rows[0].at(layout.line_index(right, kY0)), -1.0 / sigma, 1e-15);
  EXPECT_EQ(rows.rows[0].at(layout.line_index(other, kY0)), 0.0);
}

TEST(PriorResiduals, LaneWidthBetweenTheOutermostLines) {
  using enum FreeParam;
  const ParameterLayout layout(free_set({y0}), 3);
  SolverPriors priors;
  priors.lane_width_mm = Prior{7000.0, 100.0};
  const RoadLine lines[3] = {{100.0, 0, 0}, {3600.0, 0, 0}, {-3500.0, 0, 0}};
  PriorRows rows;
  double cost = 0.0;
  evaluate_priors(priors, layout, CameraPose{{}, 1400, 5}, lines, rows, cost);
  expect_width_row(rows, layout, (7100.0 - 7000.0) / 100.0, 100.0, 1, 2, 0);
  EXPECT_EQ(count_free_priors(priors, layout), 1);
  // One line has no width: the prior is ignored.
  const ParameterLayout single(free_set({y0}), 1);
  cost = 0.0;
  evaluate_priors(priors, single, CameraPose{{}, 1400, 5}, lines, rows, cost);
  EXPECT_EQ(rows.count, 0);
  EXPECT_EQ(count_free_priors(priors, single), 0);
}

// A caller who knows which lines bound one lane names them; a name out of range is the
// outermost lines again.
TEST(PriorResiduals, LaneWidthBetweenTheNamedLines) {
  using enum FreeParam;
  const ParameterLayout layout(free_set({y0}), 3);
  SolverPriors priors;
  priors.lane_width_mm = Prior{3600.0, 100.0};
  priors.lane_width_left = 0;
  priors.lane_width_right = 2;
  const RoadLine lines[3] = {{100.0, 0, 0}, {3600.0, 0, 0}, {-3550.0, 0, 0}};
  PriorRows rows;
  double cost = 0.0;
  evaluate_priors(priors, layout, CameraPose{{}, 1400, 5}, lines, rows, cost);
  expect_width_row(rows, layout, (3650.0 - 3600.0) / 100.0, 100.0, 0, 2, 1);
  priors.lane_width_left = 3;
  cost = 0.0;
  evaluate_priors(priors, layout, CameraPose{{}, 1400, 5}, lines, rows, cost);
  expect_width_row(rows, layout, (7150.0 - 3600.0) / 100.0, 100.0, 1, 2, 0);
}

TEST(PriorResiduals, RowsKeepTheirNonzeroEntriesOnly) {
  PriorRow row;
  row.add(3, 1.0);
  row.add(-1, 5.0);  // a fixed parameter: nothing to add
  row.add(3, 0.5);   // the same parameter again: summed
  row.add(1, -2.0);
  EXPECT_EQ(row.size, 2);
  EXPECT_EQ(row.at(3), 1.5);
  EXPECT_EQ(row.at(1), -2.0);
  EXPECT_EQ(row.at(0), 0.0);
}

}  // namespace
}  // namespace ccdlane::solver
