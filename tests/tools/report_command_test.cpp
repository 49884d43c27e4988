// `ccdlane report` as a user sees it: the page opened in a real browser (headless
// Chromium, a screenshot) with every plotted series drawn, the page self-contained, the
// PNG files, the summary's figures, and a bad replay file as one line and exit 2.
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/png_image.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using Json = nlohmann::json;
const std::string kTool = CCDLANE_TOOL;
constexpr const char* kChromium = "/usr/bin/chromium";

Json nullable(double v) { return std::isnan(v) ? Json(nullptr) : Json(v); }

// A 10 s drive at 30 fps with something in every series: a weaving offset, warnings on
// both sides, both TLCs, LDW unavailable for a while, frames not ok for two reasons.
std::string drive_jsonl() {
  std::ostringstream out;
  for (int k = 0; k < 300; ++k) {
    const double t = k / 30.0;
    const bool ok = !(k >= 100 && k < 112) && k % 37 != 5;
    const double offset = 600.0 * std::sin(t * 1.3), width = 3600.0 + 40.0 * std::sin(t * 3.1);
    const double dlc_left = 1000.0 - offset, dlc_right = 1000.0 + offset;
    const double vy = 0.78 * std::cos(t * 1.3);
    const char* fired = k == 40 ? "left" : k == 190 ? "right" : k == 260 ? "left" : "none";
    Json e = {{"frame", k}, {"t_ns", static_cast<std::int64_t>(k) * 33'333'333}, {"ok", ok}};
    if (!ok) e["reason"] = k < 112 && k >= 100 ? "no_lane" : "too_few_marks";
    e["lateral_offset_mm"] = ok ? Json(offset) : Json(nullptr);
    e["lane_width_mm"] = ok ? Json(width) : Json(nullptr);
    e["heading_deg"] = ok ? Json(1.5 * std::cos(t)) : Json(nullptr);
    e["curvature_per_m"] = ok ? Json(0.002 * std::sin(t / 2)) : Json(nullptr);
    e["radius_of_curvature_m"] = ok ? Json(500.0 / std::sin(t / 2 + 0.1)) : Json(nullptr);
    e["latency_us"] = 900 + (k % 7) * 150;
    e["ldw"] = {{"available", k < 150 || k >= 170},
                {"reason", k < 150 || k >= 170 ? "none" : "too_slow"},
                {"warning", fired},
                {"fired", fired},
                {"dlc_left_mm", dlc_left},
                {"dlc_right_mm", dlc_right},
                {"tlc_left_s", nullable(vy > 0.05 ? dlc_left / 1000.0 / vy : std::nan(""))},
                {"tlc_right_s", nullable(vy < -0.05 ? dlc_right / 1000.0 / -vy : std::nan(""))}};
    out << e.dump() << '\n';
  }
  return out.str();
}

// The page's own list of what each plot draws in which colour (data-series="name:#rrggbb,...").
std::map<std::string, std::array<int, 3>> series_colours(const std::string& html) {
  std::map<std::string, std::array<int, 3>> colours;
  const std::regex attribute(R"(data-series="([^"]*)\")");
  const std::regex entry(R"(([^,:]+):#([0-9a-f]{2})([0-9a-f]{2})([0-9a-f]{2}))");
  for (auto a = std::sregex_iterator(html.begin(), html.end(), attribute); a != std::sregex_iterator(); ++a) {
    const std::string list = (*a)[1];
    for (auto e = std::sregex_iterator(list.begin(), list.end(), entry); e != std::sregex_iterator(); ++e)
      colours[(*e)[1]] = {std::stoi((*e)[2], nullptr, 16), std::stoi((*e)[3], nullptr, 16),
                          std::stoi((*e)[4], nullptr, 16)};
  }
  return colours;
}

TEST(ReportCommand, ThePageShowsEverySeriesInABrowser) {
  if (::access(kChromium, X_OK) != 0) GTEST_SKIP() << "no " << kChromium << " (tools/install-deps installs it)";
  test::TempDir dir;
  const std::string replay = dir.write("drive.jsonl", drive_jsonl());
  const auto r =
      test::run_process({kTool, "report", replay, "--out", dir.file("report.html"), "--png", dir.file("png")});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const std::string html = test::read_file(dir.file("report.html"));
  // Self-contained: nothing fetched from anywhere.
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  // The summary: 300 frames, 12 + 8 not ok, 3 warnings, the longest stretch 100..111.
  EXPECT_NE(html.find("<th>ok</th><td>280 (93.3 %)</td>"), std::string::npos) << html.substr(0, 2000);
  EXPECT_NE(html.find("<th>warnings</th><td>3</td>"), std::string::npos);
  EXPECT_NE(html.find("<th>longest stretch not ok</th><td>12 frames (100 to 111)</td>"), std::string::npos);
  for (const char* plot : {"offset", "width", "heading", "dlc-tlc", "ldw", "not-ok", "latency"})
    EXPECT_TRUE(std::filesystem::file_size(dir.file(std::string("png/") + plot + ".png")) > 5000) << plot;

  const std::string shot = dir.file("shot.png");
  const auto c =
      test::run_process({kChromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                         "--disable-background-networking", "--disable-component-update", "--disable-sync",
                         "--hide-scrollbars", "--user-data-dir=" + dir.file("chromium"), "--window-size=960,2400",
                         "--screenshot=" + shot, "file://" + dir.file("report.html")});
  ASSERT_EQ(c.exit_status, 0) << c.err;
  const test::PngImage page = test::read_png(shot);
  ASSERT_EQ(page.format, PixelFormat::rgb8);
  const auto colours = series_colours(html);
  EXPECT_EQ(colours.size(), 14u);
  // Each series leaves pixels of its own colour: more than its legend's mark alone.
  for (const auto& [name, rgb] : colours) {
    int pixels = 0;
    for (int y = 0; y < page.height; ++y)
      for (int x = 0; x < page.width; ++x) {
        const std::uint8_t* p = page.view().row(y) + 3 * x;
        pixels += p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2];
      }
    EXPECT_GT(pixels, 150) << name << " is not drawn in the browser's rendering of the page";
  }
}

TEST(ReportCommand, ABadReplayFileIsOneLineAndExitTwo) {
  test::TempDir dir;
  const std::string bad = dir.write("bad.jsonl", "{\"frame\": 0, \"t_ns\": 0, \"ok\": true}\nnot json\n");
  const auto r = test::run_process({kTool, "report", bad, "--out", dir.file("r.html")});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlane report: " + bad + ":2: not a replay JSON object (Expecting value)\n");
  EXPECT_FALSE(std::filesystem::exists(dir.file("r.html")));
  const auto none = test::run_process({kTool, "report", bad});
  EXPECT_EQ(none.exit_status, 2);
}

}  // namespace
}  // namespace ccdlane
