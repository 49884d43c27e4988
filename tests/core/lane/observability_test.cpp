// Which solver set-ups can determine what they are asked for, as the enum callers decide
// on, and that each problem's explanation names the configuration keys to change.
#include "core/lane/observability.hpp"

#include <string>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

LaneEstimatorOptions with_free(std::initializer_list<FreeParam> params) {
  LaneEstimatorOptions o;
  o.solver.free = FreeSet{};
  for (FreeParam p : params) o.solver.free.add(p);
  return o;
}

TEST(Observability, RollIsObservableOnlyWithAGyroOrAPrior) {
  LaneEstimatorOptions o = with_free({FreeParam::psi, FreeParam::theta, FreeParam::phi, FreeParam::y0});
  EXPECT_EQ(observability(o, false), Observability::roll_unobservable);
  EXPECT_EQ(observability(o, true), Observability::observable);
  EXPECT_TRUE(roll_needs_gyro(o));
  o.priors.lane_width_mm = Prior{3600.0, 200.0};
  EXPECT_EQ(observability(o, false), Observability::observable);
  EXPECT_FALSE(roll_needs_gyro(o));
}

TEST(Observability, ScaleAndFocalLengthComeFirstAndNoGyroMendsThem) {
  const LaneEstimatorOptions h = with_free({FreeParam::psi, FreeParam::H, FreeParam::phi, FreeParam::y0});
  EXPECT_EQ(observability(h, true), Observability::height_unobservable);
  EXPECT_EQ(observability(h, false), Observability::height_unobservable);
  EXPECT_FALSE(roll_needs_gyro(h));
  const LaneEstimatorOptions f = with_free({FreeParam::psi, FreeParam::f, FreeParam::y0});
  EXPECT_EQ(observability(f, true), Observability::focal_unobservable);
}

TEST(Observability, ExplanationsNameTheKeys) {
  EXPECT_STREQ(explain(Observability::observable), "");
  EXPECT_NE(std::string(explain(Observability::height_unobservable)).find("[prior] H_mm"), std::string::npos);
  EXPECT_NE(std::string(explain(Observability::focal_unobservable)).find("[prior] f_mm"), std::string::npos);
  EXPECT_NE(std::string(explain(Observability::roll_unobservable)).find("[prior] phi_deg"), std::string::npos);
}

}  // namespace
}  // namespace ccdlane
