// Road lines in the picture: the column found at a row is where the camera model puts
// the line's point on that row; rows the line does not reach have none.
#include "tools/ccdlane/road_line_picture.hpp"

#include <gtest/gtest.h>

#include "app/config.hpp"

namespace ccdlane::cli {
namespace {

TEST(RoadLinePicture, ColumnAtRowIsTheProjectedPointOnThatRow) {
  Config c = default_config();
  c.attitude.phi_deg = 1.5;  // rows tilt: the row of a point depends on its side too
  const CameraModel cam(c.camera, c.nominal_pose());
  const RoadLine line{-1700, 0.02, 2e-7};
  for (const double x_mm : {4000.0, 9000.0, 25000.0, 60000.0}) {
    const Vec2 p = *cam.pixel_from_point(Vec3(x_mm, line.y_at(x_mm), 0));
    const auto column = road_line_column_at_row(cam, line, p.y(), 500, 300000);
    ASSERT_TRUE(column) << x_mm;
    EXPECT_NEAR(*column, p.x(), 1e-6) << x_mm;
  }
  // Above the far end and below the near end: no crossing.
  const Vec2 far = *cam.pixel_from_point(Vec3(30000, line.y_at(30000), 0));
  EXPECT_FALSE(road_line_column_at_row(cam, line, far.y() - 2, 5000, 30000));
  const Vec2 near = *cam.pixel_from_point(Vec3(5000, line.y_at(5000), 0));
  EXPECT_FALSE(road_line_column_at_row(cam, line, near.y() + 2, 5000, 30000));
  // The sampled pixels are the line's points at evenly spaced distances.
  const auto pixels = road_line_pixels(cam, line, 5000, 30000, 5);
  ASSERT_EQ(pixels.size(), 6u);
  EXPECT_NEAR((*pixels[1] - *cam.pixel_from_point(Vec3(10000, line.y_at(10000), 0))).norm(), 0.0, 1e-9);
}

// A pincushion lens (k_px2 > 0) has an edge to its field: a point far off the axis (the
// line half a metre ahead, beside the car) has no observed pixel. The rows the line does
// cross in the picture still have their column: the scan starts where its points begin to
// project (with the near end off the field, TuSimple's stills scored with k_px2 = +5e-8
// had no line on any row).
TEST(RoadLinePicture, APincushionLensStillHasTheColumnsOfTheRowsTheLineCrosses) {
  Config c = default_config();
  c.camera.k_px2 = 5e-7;
  const CameraModel cam(c.camera, c.nominal_pose());
  const RoadLine line{-1700, 0.02, 2e-7};
  ASSERT_FALSE(cam.pixel_from_point(Vec3(500, line.y_at(500), 0))) << "the near end lies beyond the lens's field";
  for (const double x_mm : {4000.0, 9000.0, 25000.0, 60000.0}) {
    const auto p = cam.pixel_from_point(Vec3(x_mm, line.y_at(x_mm), 0));
    ASSERT_TRUE(p) << x_mm;
    const auto column = road_line_column_at_row(cam, line, p->y(), 500, 300000);
    ASSERT_TRUE(column) << x_mm;
    EXPECT_NEAR(*column, p->x(), 1e-6) << x_mm;
  }
}

}  // namespace
}  // namespace ccdlane::cli
