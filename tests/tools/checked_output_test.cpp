// Every subcommand that prints, with its output on a full device (/dev/full): exit 1
// with the reason, never exit 0 with the output lost.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

const std::string kTool = CCDLANE_TOOL;
const std::string kSource = CCDLANE_SOURCE_DIR;
const std::string kReferenceCamera = kSource + "/tools/demo/reference-camera.toml";

// Runs the tool with standard output on /dev/full.
test::ProcessResult run_into_full_device(const std::vector<std::string>& args) {
  std::vector<std::string> argv{"/bin/sh", "-c", "exec \"$@\" >/dev/full", "sh", kTool};
  argv.insert(argv.end(), args.begin(), args.end());
  return test::run_process(argv);
}

void expect_write_failure(const test::ProcessResult& r, const std::string& what) {
  EXPECT_EQ(r.exit_status, 1) << r.err;
  EXPECT_NE(r.err.find(what + ": cannot write: No space left on device"), std::string::npos) << r.err;
}

TEST(CheckedOutput, GeometryCommandsOnAFullDeviceExitOne) {
  SCOPED_TRACE("project");
  expect_write_failure(run_into_full_device({"project", kReferenceCamera, "20000", "0", "0"}), "standard output");
  SCOPED_TRACE("ground");
  expect_write_failure(run_into_full_device({"ground", kReferenceCamera, "400", "500"}), "standard output");
}

TEST(CheckedOutput, SolveOnAFullDeviceExitsOne) {
  expect_write_failure(run_into_full_device({"solve", kSource + "/tools/demo/paper-table1a.toml"}), "standard output");
}

TEST(CheckedOutput, ReplayToAFullDeviceOrFullOutFileExitsOne) {
  test::TempDir dir;
  const auto s = test::run_process({kTool, "synth", kReferenceCamera, "--out", dir.file("road"), "--frames", "3"});
  ASSERT_EQ(s.exit_status, 0) << s.err;
  expect_write_failure(run_into_full_device({"replay", kReferenceCamera, dir.file("road")}), "standard output");
  const auto r = test::run_process({kTool, "replay", kReferenceCamera, dir.file("road"), "--out", "/dev/full"});
  expect_write_failure(r, "/dev/full");
}

}  // namespace
}  // namespace ccdlane
