// `ccdlane solve` as a user runs it: the paper's picture through the demo problem file,
// a synthetic truth recovered through the JSON, and one clear line (exit 2) for every
// kind of bad problem or picks file.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/core/solver/synthetic_scene.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using Json = nlohmann::ordered_json;
const std::string kTool = CCDLANE_TOOL;
const std::string kDemo = std::string(CCDLANE_SOURCE_DIR) + "/tools/demo/paper-table1a.toml";
const std::string kPaperPicks = std::string(CCDLANE_TEST_DATA_DIR) + "/paper/table1_a.csv";

// The demo problem without its picks key: for tests that bring their own picks.
std::string problem_without_picks(const std::string& extra = "") {
  std::string text = test::read_file(kDemo);
  const std::size_t at = text.find("picks = ");
  text.erase(at, text.find('\n', at) - at + 1);
  return text + extra;
}

Json solve_ok(const std::vector<std::string>& args) {
  std::vector<std::string> argv{kTool, "solve"};
  argv.insert(argv.end(), args.begin(), args.end());
  const auto r = test::run_process(argv);
  EXPECT_EQ(r.exit_status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  return Json::parse(r.out);
}

// Runs a failing solve; returns its one line of stderr.
std::string solve_error(const std::vector<std::string>& args) {
  std::vector<std::string> argv{kTool, "solve"};
  argv.insert(argv.end(), args.begin(), args.end());
  const auto r = test::run_process(argv);
  EXPECT_EQ(r.exit_status, 2) << r.out;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  return r.err;
}

TEST(SolveCommand, DemoProblemSolvesThePapersPictureA) {
  const Json j = solve_ok({kDemo});
  // Exactly the fields of docs/interfaces.md, in its order.
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items()) keys.push_back(k);
  EXPECT_EQ(keys,
            (std::vector<std::string>{"mode", "converged", "rank_deficient", "iterations", "cost", "rms_px", "psi_deg",
                                      "theta_deg", "phi_deg", "H_mm", "f_mm", "lines", "points", "sigma"}));
  EXPECT_EQ(j["mode"], "reprojection");
  EXPECT_EQ(j["converged"], true);
  EXPECT_EQ(j["rank_deficient"], false);
  EXPECT_NEAR(j["psi_deg"].get<double>(), 0.0, 0.5);
  EXPECT_NEAR(j["theta_deg"].get<double>(), 0.0, 0.5);
  EXPECT_EQ(j["H_mm"], 1000.0);
  EXPECT_EQ(j["f_mm"], 5.05);
  ASSERT_EQ(j["lines"].size(), 2u);
  EXPECT_EQ(j["lines"][1]["id"], 1);
  EXPECT_NEAR(j["lines"][0]["y0_mm"].get<double>() / 1027.25, 1.0, 0.05);  // one lens height aside
  EXPECT_NEAR(j["lines"][1]["y0_mm"].get<double>() / 1027.25, -1.0, 0.05);
  EXPECT_EQ(j["lines"][0]["m"], 0.0);
  // Every pick, in file order, with its mark on its line.
  ASSERT_EQ(j["points"].size(), 10u);
  EXPECT_EQ(j["points"][5]["line"], 1);
  EXPECT_EQ(j["points"][5]["px"], 571.0);
  EXPECT_EQ(j["points"][5]["py"], 509.0);
  EXPECT_EQ(j["points"][5]["y_mm"], j["lines"][1]["y0_mm"]);
  EXPECT_GT(j["points"][9]["x_mm"].get<double>(), j["points"][5]["x_mm"].get<double>());  // nearest first
  // Sigma for the free parameters only.
  const Json& s = j["sigma"];
  EXPECT_EQ(s.size(), 4u);
  EXPECT_GT(s["psi_deg"].get<double>(), 0.0);
  EXPECT_NEAR(s["phi_deg"].get<double>(), 1.0, 0.01);  // roll: its prior alone
  ASSERT_EQ(s["y0_mm"].size(), 2u);
  EXPECT_GT(s["y0_mm"][1].get<double>(), 0.0);
}

TEST(SolveCommand, PicksOptionAndPicksKeyRelativeToTheProblem) {
  test::TempDir dir;
  const Json reference = solve_ok({kDemo});
  const std::string bare = dir.write("bare.toml", problem_without_picks());
  EXPECT_EQ(solve_ok({bare, "--picks", kPaperPicks})["psi_deg"], reference["psi_deg"]);
  // [solver] picks is relative to the problem file, not to the working directory.
  std::filesystem::create_directories(dir.file("data"));
  dir.write("data/a.csv", test::read_file(kPaperPicks));
  std::string with_key = problem_without_picks();
  with_key.replace(with_key.find("[solver]\n"), 9, "[solver]\npicks = \"data/a.csv\"\n");
  EXPECT_EQ(solve_ok({dir.write("keyed.toml", with_key)})["psi_deg"], reference["psi_deg"]);
}

TEST(SolveCommand, RecoversASyntheticTruthThroughTheJson) {
  std::mt19937_64 rng(5);
  const test::SyntheticScene scene = test::make_scene(rng, {});
  std::ostringstream csv;
  csv.precision(17);
  csv << "line,px,py\n";
  for (const Pick& p : scene.picks) csv << p.line << ',' << p.px << ',' << p.py << '\n';
  const Attitude& t = scene.truth.attitude;
  std::ostringstream toml;  // the reference camera is the default; roll fixed at the truth
  toml.precision(17);
  toml << "[mount]\nH_mm = " << scene.truth.H_mm << "\n[attitude]\ntheta_deg = " << rad_to_deg(t.theta) + 1.0
       << "\nphi_deg = " << rad_to_deg(t.phi) << "\n[solver]\nfree = [\"psi\", \"theta\", \"y0\"]\npicks = \"p.csv\"\n";
  test::TempDir dir;
  dir.write("p.csv", csv.str());
  const Json j = solve_ok({dir.write("truth.toml", toml.str())});
  EXPECT_EQ(j["converged"], true);
  EXPECT_NEAR(j["psi_deg"].get<double>(), rad_to_deg(t.psi), 1e-6);
  EXPECT_NEAR(j["theta_deg"].get<double>(), rad_to_deg(t.theta), 1e-6);
  EXPECT_NEAR(j["lines"][0]["y0_mm"].get<double>(), scene.lines[0].y0_mm, 1e-6);
  EXPECT_NEAR(j["lines"][1]["y0_mm"].get<double>(), scene.lines[1].y0_mm, 1e-6);
  for (std::size_t i = 0; i < scene.picks.size(); ++i)
    EXPECT_NEAR(j["points"][i]["x_mm"].get<double>(), scene.x_mm[i], 1e-6 * scene.x_mm[i]);
  EXPECT_LT(j["rms_px"].get<double>(), 1e-6);
}

TEST(SolveCommand, RankDeficientProblemSaysSoWithNullSigmas) {
  test::TempDir dir;
  // Free roll and offsets with no roll prior: the paper's own ambiguity.
  std::string text = problem_without_picks();
  text.erase(text.find("[prior]"));
  const Json j = solve_ok({dir.write("p.toml", text), "--picks", kPaperPicks});
  EXPECT_EQ(j["rank_deficient"], true);
  EXPECT_TRUE(j["sigma"]["phi_deg"].is_null());
  EXPECT_TRUE(j["sigma"]["y0_mm"][0].is_null());
}

class SolveCommandErrors : public ::testing::Test {
 protected:
  std::string problem(const std::string& extra = "") { return dir.write("p.toml", problem_without_picks(extra)); }
  std::string picks(const std::string& text) { return dir.write("p.csv", text); }
  test::TempDir dir;
};

TEST_F(SolveCommandErrors, UnknownLineIdNamesFileLineAndField) {
  const std::string lines = "[[lines]]\ny0_mm = 1000.0\n[[lines]]\ny0_mm = -1000.0\n";
  const std::string csv = picks("line,px,py\n0,191,501\n1,571,509\n2,300,450\n0,223,470\n1,539,476\n");
  EXPECT_EQ(solve_error({problem(lines), "--picks", csv}),
            "ccdlane: " + csv + ":4: line: unknown lane-line id 2 (" + dir.file("p.toml") + " has [[lines]] 0..1)\n");
  // Without [[lines]] ids must run 0..N-1 and stay within the solver's lines.
  EXPECT_EQ(solve_error({problem(), "--picks", picks("line,px,py\n0,191,501\n2,571,509\n")}),
            "ccdlane: " + csv + ": lane line 1 has no picks (ids must run 0..2, or list the lines as [[lines]] in " +
                dir.file("p.toml") + ")\n");
  EXPECT_NE(solve_error({problem(), "--picks", picks("line,px,py\n9,191,501\n")}).find(":2: line: lane-line id 9"),
            std::string::npos);
}

TEST_F(SolveCommandErrors, NonNumericFieldNamesFileLineAndField) {
  const std::string csv = picks("# hand picks\nline,px,py\n0,191,501\n0,22x,470\n");
  EXPECT_EQ(solve_error({problem(), "--picks", csv}), "ccdlane: " + csv + ":4: px: not a finite number: \"22x\"\n");
}

TEST_F(SolveCommandErrors, FewerPicksThanUnknowns) {
  // psi theta phi + 2 y0 = 5 unknowns with 2 priors on them: 3 picks needed.
  const std::string csv = picks("line,px,py\n0,191,501\n1,571,509\n");
  EXPECT_EQ(solve_error({problem(), "--picks", csv}),
            "ccdlane: " + csv + ": 2 picks, but " + dir.file("p.toml") +
                "'s free parameters need at least 3 (each pick gives two equations and adds its own unknown x)\n");
}

TEST_F(SolveCommandErrors, PickAboveTheHorizon) {
  const std::string csv = picks("line,px,py\n0,191,501\n0,223,470\n1,571,509\n1,400,10\n");
  EXPECT_EQ(solve_error({problem(), "--picks", csv}),
            "ccdlane: " + csv + ":5: pick (400, 10): its ray misses the road at the initial attitude ([attitude] of " +
                dir.file("p.toml") + "): at or above the horizon\n");
}

TEST_F(SolveCommandErrors, PicksOutsideTheImageAreRefusedAsSuch) {
  // Each on its own, among picks that would solve: below, right of, left of the picture,
  // and far beyond it (which used to be called "at or above the horizon").
  for (const std::string pick : {"0,-100,501", "1,900,590", "0,0.1,700", "1,99999,500", "0,400,601"}) {
    SCOPED_TRACE(pick);
    const std::string csv = picks("line,px,py\n0,191,501\n0,223,470\n1,571,509\n1,539,476\n" + pick + "\n");
    const std::string e = solve_error({problem(), "--picks", csv});
    EXPECT_EQ(e.rfind("ccdlane: " + csv + ":6: pick (", 0), 0u) << e;
    EXPECT_NE(e.find(") is outside the image (px 0.5..800.5, py 0.5..600.5 for the 800x600 camera of " +
                     dir.file("p.toml") + ")\n"),
              std::string::npos)
        << e;
  }
}

TEST_F(SolveCommandErrors, AGarbagePicksFileIsQuotedShortAndEscaped) {
  std::string garbage = "line,px,py\n0,";
  for (int i = 0; i < 200; ++i) garbage += static_cast<char>(i % 2 ? 0x1b : 0xfe);
  const std::string e = solve_error({problem(), "--picks", picks(garbage + ",1\n")});
  EXPECT_LT(e.size(), 300u) << e;
  EXPECT_EQ(e.find('\x1b'), std::string::npos) << "no raw control byte reaches the terminal";
  EXPECT_NE(e.find("px: not a finite number: \"\\xfe\\x1b\\xfe"), std::string::npos) << e;
  EXPECT_NE(e.find("\"... (200 bytes)"), std::string::npos) << e;
}

TEST_F(SolveCommandErrors, MissingOrUnreadablePicksAndBadProblems) {
  EXPECT_EQ(solve_error({problem()}),
            "ccdlane: " + dir.file("p.toml") + ": no picks: give --picks FILE.csv or [solver] picks = \"FILE.csv\"\n");
  EXPECT_EQ(solve_error({problem(), "--picks", dir.file("none.csv")}),
            "ccdlane: " + dir.file("none.csv") + ": cannot read the picks file\n");
  const std::string bad = dir.write("bad.toml", "[solver]\nfree = [\"psi\", \"yaw\"]\n");
  EXPECT_NE(solve_error({bad, "--picks", kPaperPicks}).find(bad + ":2: solver.free: unknown parameter \"yaw\""),
            std::string::npos);
  EXPECT_NE(solve_error({dir.file("absent.toml")}).find("absent.toml: cannot read the configuration file"),
            std::string::npos);
}

}  // namespace
}  // namespace ccdlane
