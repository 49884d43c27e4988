// The bounds of a road vehicle's attitude: inside them every reading is taken, beyond
// them (or not a number) the offending angle is named.
#include "drivers/gx1/vehicle_attitude.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

namespace ccdlane::gx1 {
namespace {

std::string why(double roll, double pitch, double yaw) {
  const char* w = implausible_vehicle_angle(Gx1Angles{roll, pitch, yaw});
  return w ? w : "";
}

TEST(VehicleAttitude, TakesWhatAVehicleCanHave) {
  EXPECT_EQ(why(0.0, 0.0, 0.0), "");
  EXPECT_EQ(why(kMaxVehicleRollDeg, -kMaxVehiclePitchDeg, 180.0), "");
  EXPECT_EQ(why(-kMaxVehicleRollDeg, kMaxVehiclePitchDeg, -180.0), "");
}

TEST(VehicleAttitude, NamesTheAngleBeyondItsBound) {
  EXPECT_EQ(why(175.0, 0.0, 0.0), "roll");
  EXPECT_EQ(why(0.0, 170.0, 0.0), "pitch");
  EXPECT_EQ(why(0.0, -60.5, 0.0), "pitch");
  EXPECT_EQ(why(0.0, 0.0, 181.0), "yaw");
  EXPECT_EQ(why(NAN, 0.0, 0.0), "roll");
  EXPECT_EQ(why(0.0, NAN, 0.0), "pitch");
  EXPECT_EQ(why(0.0, 0.0, INFINITY), "yaw");
}

}  // namespace
}  // namespace ccdlane::gx1
