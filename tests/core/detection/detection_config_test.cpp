// The [detection] table of the configuration: defaults, every key, strict errors.
#include <gtest/gtest.h>

#include "app/config_loader.hpp"
#include "tests/support/config_error.hpp"

namespace ccdlane {
namespace {

std::string error_of(const std::string& toml) { return test::config_error_of(toml, "d.toml"); }

TEST(DetectionConfig, DefaultsAndEveryKey) {
  const Config d = parse_config("", "empty.toml");
  EXPECT_EQ(d.detection.mark_width_mm, 130.0);
  EXPECT_EQ(d.detection.max_lines, 4);
  EXPECT_EQ(d.detection.min_range_mm, 3000.0);
  EXPECT_EQ(d.detection.min_mark_width_mm, 100.0);
  EXPECT_EQ(d.detection.max_mark_width_mm, 300.0);
  EXPECT_EQ(d.detection.roi_top_px, 0);
  EXPECT_EQ(d.detection.hood_px, 0);
  const Config c = parse_config(R"([detection]
mark_width_mm = 150
min_contrast = 20
min_range_mm = 5500
max_range_mm = 30000
max_lines = 3
max_picks = 100
min_marks = 10
departure_mm = 1000
min_mark_width_mm = 120
max_mark_width_mm = 250
roi_top_px = 100
hood_px = 60
)",
                                "d.toml");
  EXPECT_EQ(c.detection.mark_width_mm, 150.0);
  EXPECT_EQ(c.detection.min_contrast, 20.0);
  EXPECT_EQ(c.detection.min_range_mm, 5500.0);
  EXPECT_EQ(c.detection.max_range_mm, 30000.0);
  EXPECT_EQ(c.detection.max_lines, 3);
  EXPECT_EQ(c.detection.max_picks, 100);
  EXPECT_EQ(c.detection.min_marks, 10);
  EXPECT_EQ(c.detection.departure_mm, 1000.0);
  EXPECT_EQ(c.detection.min_mark_width_mm, 120.0);
  EXPECT_EQ(c.detection.max_mark_width_mm, 250.0);
  EXPECT_EQ(c.detection.roi_top_px, 100);
  EXPECT_EQ(c.detection.hood_px, 60);
}

TEST(DetectionConfig, StrictErrors) {
  EXPECT_EQ(error_of("[detection]\nmax_lines = 5\n"), "d.toml:2: detection.max_lines: must be 2..4");
  EXPECT_EQ(error_of("[detection]\nmin_range_mm = 30000\n"),
            "d.toml:1: detection.max_range_mm: must be more than 1.5 x min_range_mm and <= 200000");
  EXPECT_EQ(error_of("[detection]\nmark_width = 100\n"), "d.toml:2: detection.mark_width: unknown key");
  EXPECT_EQ(error_of("[detection]\nmin_contrast = 0\n"), "d.toml:2: detection.min_contrast: must be > 0 and <= 200");
  EXPECT_EQ(error_of("[detection]\nmark_width_mm = 400\n"),
            "d.toml:2: detection.mark_width_mm: must lie within min_mark_width_mm .. max_mark_width_mm (100 .. 300); "
            "set those too");
  EXPECT_EQ(error_of("[detection]\nmin_mark_width_mm = 300\n"),
            "d.toml:2: detection.min_mark_width_mm: must be 30 .. max_mark_width_mm (300)");
  EXPECT_EQ(error_of("[detection]\nhood_px = -1\n"), "d.toml:2: detection.hood_px: must be >= 0");
  // The reference camera's picture is 600 rows high.
  EXPECT_EQ(error_of("[detection]\nroi_top_px = 300\nhood_px = 291\n"),
            "d.toml:3: detection.hood_px: roi_top_px + hood_px must leave at least 10 rows of the picture's 600");
}

}  // namespace
}  // namespace ccdlane
