// The calibrate commands' output: TOML floats read back to the same double, and a table
// written atomically (whole, no temporary left behind; an unwritable place throws).
#include "tools/ccdlane/calibration_output.hpp"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/run_process.hpp"
#include "tools/ccdlane/checked_output.hpp"

namespace ccdlane::cli {
namespace {

TEST(CalibrationOutput, TomlFloatsReadBackExactly) {
  for (double v : {0.0, 1.0, -2.5, 1537.6253023453428, 1e-7, -8.3042e-7, 1e20}) {
    const std::string s = toml_float(v);
    EXPECT_EQ(std::stod(s), v) << s;
    EXPECT_NE(s.find_first_of(".eE"), std::string::npos) << s;  // a float, not an integer
  }
  EXPECT_EQ(fixed(1.23456, 2), "1.23");
}

TEST(CalibrationOutput, WritesWholeAndLeavesNoTemporary) {
  test::TempDir dir;
  const std::string path = dir.file("t.toml");
  write_file_checked(path, "[mount]\nH_mm = 1.0\n");
  std::ifstream in(path);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_EQ(text, "[mount]\nH_mm = 1.0\n");
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(path).parent_path()))
    ++files;
  EXPECT_EQ(files, 1u) << "no temporary left beside it";
  EXPECT_THROW(write_file_checked(dir.file("no/such/dir/t.toml"), "x"), std::runtime_error);
}

}  // namespace
}  // namespace ccdlane::cli
