// Replay's output lines as score reads them: solved and unsolved frames, and every kind
// of damage as one message naming the field (a `lines` entry of {} once crashed score).
#include "tools/ccdlane/replay_line.hpp"

#include <gtest/gtest.h>

namespace ccdlane::cli {
namespace {

TEST(ReplayLine, ReadsASolvedFrame) {
  ReplayLine r;
  ASSERT_EQ(parse_replay_line(R"({"frame": 7, "ok": true, "psi_deg": 1.5, "theta_deg": 0.5, "phi_deg": -0.25,
                                  "lines": [{"y0_mm": -1800, "m": 0.01, "c_per_mm": 1e-7}]})",
                              r),
            "");
  EXPECT_EQ(r.frame, 7u);
  ASSERT_TRUE(r.attitude);
  EXPECT_EQ(r.attitude->theta_deg, 0.5);
  EXPECT_FALSE(r.attitude->H_mm) << "written before the height was: the configuration's";
  ASSERT_EQ(r.lines.size(), 1u);
  EXPECT_EQ(r.lines[0].y0_mm, -1800.0);
  EXPECT_EQ(r.lines[0].c_per_mm, 1e-7);
  ASSERT_EQ(r.near_mm.size(), 1u);
  EXPECT_FALSE(r.near_mm[0]) << "written before view ranges were: not said";
}

TEST(ReplayLine, ReadsWhereEachLinesNearestMarkIs) {
  ReplayLine r;
  ASSERT_EQ(parse_replay_line(R"({"frame": 7, "psi_deg": 1.5, "theta_deg": 0.5, "phi_deg": -0.25,
                                  "lines": [{"y0_mm": 1700, "m": 0, "c_per_mm": 0, "near_mm": 6250.5},
                                            {"y0_mm": -1800, "m": 0, "c_per_mm": 0, "near_mm": null}]})",
                              r),
            "");
  ASSERT_EQ(r.near_mm.size(), 2u);
  ASSERT_TRUE(r.near_mm[0]);
  EXPECT_EQ(*r.near_mm[0], 6250.5);
  EXPECT_FALSE(r.near_mm[1]);
}

TEST(ReplayLine, ReadsTheHeightTheLinesAreAt) {
  ReplayLine r;
  ASSERT_EQ(parse_replay_line(R"({"frame": 7, "psi_deg": 1.5, "theta_deg": 0.5, "phi_deg": -0.25, "H_mm": 1680.5})", r),
            "");
  ASSERT_TRUE(r.attitude && r.attitude->H_mm);
  EXPECT_EQ(*r.attitude->H_mm, 1680.5);
  ASSERT_EQ(parse_replay_line(R"({"frame": 7, "psi_deg": 1.5, "theta_deg": 0.5, "phi_deg": -0.25, "H_mm": null})", r),
            "");
  EXPECT_FALSE(r.attitude->H_mm);
}

TEST(ReplayLine, AnUnsolvedFrameHasNoAttitude) {
  ReplayLine r;
  ASSERT_EQ(parse_replay_line(R"({"frame": 3, "ok": false, "psi_deg": null, "lines": null})", r), "");
  EXPECT_EQ(r.frame, 3u);
  EXPECT_FALSE(r.attitude);
  ASSERT_EQ(parse_replay_line(R"({"frame": 4})", r), "");
  EXPECT_FALSE(r.attitude);
}

TEST(ReplayLine, DamageIsOneMessageNamingTheField) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "not a JSON object"},
      {"[1, 2]", "not a JSON object"},
      {R"({"ok": true})", "frame: not a frame number"},
      {R"({"frame": -1})", "frame: not a frame number"},
      {R"({"frame": "7"})", "frame: not a frame number"},
      {R"({"frame": 1.5})", "frame: not a frame number"},
      {R"({"frame": 1, "psi_deg": "x"})", "psi_deg: not a number"},
      {R"({"frame": 1, "psi_deg": 1})", "theta_deg: not a number"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": true})", "phi_deg: not a number"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 1, "H_mm": "high"})", "H_mm: not a height"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 1, "H_mm": -1300})", "H_mm: not a height"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 1, "lines": 5})", "lines: not an array"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 1, "lines": [{}]})", "lines[0].y0_mm: not a number"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 1, "lines": [{"y0_mm": 1, "m": 0, "c_per_mm": 0}, 3]})",
       "lines[1]: not an object"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 1, "lines": [{"y0_mm": 1, "m": null}]})",
       "lines[0].m: not a number"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 1,
           "lines": [{"y0_mm": 1, "m": 0, "c_per_mm": 0, "near_mm": "near"}]})",
       "lines[0].near_mm: not a distance"},
      {R"({"frame": 1, "psi_deg": 1, "theta_deg": 1, "phi_deg": 1,
           "lines": [{"y0_mm": 1, "m": 0, "c_per_mm": 0, "near_mm": -5}]})",
       "lines[0].near_mm: not a distance"},
  };
  for (const auto& [text, why] : cases) {
    ReplayLine r;
    EXPECT_EQ(parse_replay_line(text, r), why) << text;
  }
}

}  // namespace
}  // namespace ccdlane::cli
