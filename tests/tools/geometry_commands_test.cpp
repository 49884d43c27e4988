// `ccdlane project` / `ccdlane ground` as a user runs them, against docs/geometry.md written
// out literally (plain arrays, the specification's own forms of every formula), on poses
// and points that are not in the vectors file.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using Json = nlohmann::json;
using V3 = std::array<double, 3>;
using M3 = std::array<V3, 3>;

struct SpecCamera {
  double U = 6.4, V = 4.8, Uc = 0.0042, Vc = 0.0042;
  int Nu = 800, Nv = 600;
  double cx = 400.5, cy = 300.5, k = -8.3042e-7, yM = -27.25, zM = 2.53;
  double f = 5.05, H = 1400, psi = 0, theta = 0, phi = 0;  // degrees

  M3 T() const {
    const double d = 3.14159265358979323846 / 180;
    const double a = psi * d, b = theta * d, c = phi * d;
    const M3 rz{{{cos(a), -sin(a), 0}, {sin(a), cos(a), 0}, {0, 0, 1}}};
    const M3 ry{{{cos(b), 0, sin(b)}, {0, 1, 0}, {-sin(b), 0, cos(b)}}};
    const M3 rx{{{1, 0, 0}, {0, cos(c), -sin(c)}, {0, sin(c), cos(c)}}};
    const M3 p{{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}};
    return mul(mul(mul(rz, ry), rx), p);
  }
  static M3 mul(const M3& x, const M3& y) {
    M3 r{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) r[i][j] += x[i][k] * y[k][j];
    return r;
  }
  static V3 apply(const M3& m, const V3& v) {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
  }
  double pu() const { return (U - Uc) / (Nu - 1); }
  double pv() const { return (V - Vc) / (Nv - 1); }
  V3 O_F() const {
    const V3 t = apply(T(), {0, yM, zM});
    return {-t[0], -t[1], H - t[2]};
  }
  V3 L() const {
    const V3 o = O_F(), t = apply(T(), {0, 0, f});
    return {o[0] + t[0], o[1] + t[1], o[2] + t[2]};
  }

  // Road -> pixel, as "From road to pixel" then "Radial distortion" say.
  std::optional<std::array<double, 2>> project(const V3& X) const {
    const M3 t = T();
    const V3 l = L();
    const V3 rel{X[0] - l[0], X[1] - l[1], X[2] - l[2]};
    V3 d{};
    for (int i = 0; i < 3; ++i) d[i] = t[0][i] * rel[0] + t[1][i] * rel[1] + t[2][i] * rel[2];
    if (d[2] <= 0) return std::nullopt;
    const double ux = cx - f * d[0] / (d[2] * pu()), uy = cy - f * d[1] / (d[2] * pv());
    const double ru = std::hypot(ux - cx, uy - cy);
    if (k == 0 || ru == 0) return std::array<double, 2>{ux, uy};
    if (4 * k * ru * ru > 1) return std::nullopt;
    const double rd = (1 - std::sqrt(1 - 4 * k * ru * ru)) / (2 * k * ru);
    return std::array<double, 2>{cx + (ux - cx) * rd / ru, cy + (uy - cy) * rd / ru};
  }

  // Pixel -> road, as "Pixels and chip cells" and "From pixel to road" say.
  std::optional<V3> ground(double px, double py) const {
    const double den = 1 + k * ((px - cx) * (px - cx) + (py - cy) * (py - cy));
    if (den <= 0) return std::nullopt;
    const double ux = cx + (px - cx) / den, uy = cy + (py - cy) / den;
    const V3 o = O_F(), c = apply(T(), {(ux - cx) * pu(), (uy - cy) * pv(), 0});
    const V3 P{o[0] + c[0], o[1] + c[1], o[2] + c[2]}, l = L();
    if (P[2] - l[2] <= 0) return std::nullopt;
    return V3{l[0] - l[2] * (P[0] - l[0]) / (P[2] - l[2]), l[1] - l[2] * (P[1] - l[1]) / (P[2] - l[2]), 0.0};
  }

  std::string toml() const {
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "[camera]\nU_mm = %.17g\nV_mm = %.17g\nUc_mm = %.17g\nVc_mm = %.17g\nNu = %d\nNv = %d\n"
                  "f_mm = %.17g\ncx = %.17g\ncy = %.17g\nk_px2 = %.17g\n"
                  "[mount]\nyM_mm = %.17g\nzM_mm = %.17g\nH_mm = %.17g\n"
                  "[attitude]\npsi_deg = %.17g\ntheta_deg = %.17g\nphi_deg = %.17g\n",
                  U, V, Uc, Vc, Nu, Nv, f, cx, cy, k, yM, zM, H, psi, theta, phi);
    return buf;
  }
};

const std::string kTool = CCDLANE_TOOL;

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

TEST(GeometryCommands, AgreeWithTheSpecificationOnRandomPoses) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<> ang(-30, 30), u01(0, 1);
  test::TempDir dir;
  int projected = 0, grounded = 0, nulls = 0;
  for (int trial = 0; trial < 60; ++trial) {
    SpecCamera cam;
    cam.psi = ang(rng);
    cam.theta = 5 + 25 * u01(rng);  // looking down enough to see road
    cam.phi = ang(rng);
    cam.f = 3 + 9 * u01(rng);
    cam.H = 300 + 2500 * u01(rng);
    cam.cx = 380 + 40 * u01(rng);
    cam.cy = 280 + 40 * u01(rng);
    cam.k = -1.5e-6 + 1.9e-6 * u01(rng);
    if (trial % 5 == 0) cam.k = 0;
    const std::string config = dir.write("cam" + std::to_string(trial) + ".toml", cam.toml());

    const double px = 1 + 799 * u01(rng), py = 1 + 599 * u01(rng);
    const auto g = test::run_process({kTool, "ground", config, num(px), num(py)});
    ASSERT_EQ(g.exit_status, 0) << g.err;
    const Json gj = Json::parse(g.out);
    const auto want_g = cam.ground(px, py);
    if (!want_g) {
      EXPECT_TRUE(gj["ground_mm"].is_null()) << g.out;
      ++nulls;
    } else {
      ASSERT_FALSE(gj["ground_mm"].is_null()) << g.out;
      for (int i = 0; i < 2; ++i)
        EXPECT_LE(std::abs(gj["ground_mm"][i].get<double>() - (*want_g)[i]),
                  1e-6 * std::hypot((*want_g)[0], (*want_g)[1]));
      EXPECT_EQ(gj["ground_mm"][2].get<double>(), 0.0);
      ++grounded;
    }

    const V3 X{2000 + 40000 * u01(rng), -8000 + 16000 * u01(rng), trial % 3 == 0 ? 500 * u01(rng) : 0.0};
    const auto p = test::run_process({kTool, "project", config, num(X[0]), num(X[1]), num(X[2])});
    ASSERT_EQ(p.exit_status, 0) << p.err;
    const Json pj = Json::parse(p.out);
    const auto want_p = cam.project(X);
    if (!want_p) {
      EXPECT_TRUE(pj["pixel"].is_null()) << p.out;
      ++nulls;
    } else {
      ASSERT_FALSE(pj["pixel"].is_null()) << p.out;
      EXPECT_NEAR(pj["pixel"][0].get<double>(), (*want_p)[0], 1e-6);
      EXPECT_NEAR(pj["pixel"][1].get<double>(), (*want_p)[1], 1e-6);
      ++projected;
    }
  }
  EXPECT_GT(projected, 30);
  EXPECT_GT(grounded, 20);
  EXPECT_GT(nulls, 0);  // horizon and behind-camera cases did come up
}

TEST(GeometryCommands, PrintsFullPrecision) {
  test::TempDir dir;
  SpecCamera cam;
  const auto p =
      test::run_process({kTool, "project", dir.write("c.toml", cam.toml()), "20563.78156", "3726.979864", "0"});
  ASSERT_EQ(p.exit_status, 0);
  const Json j = Json::parse(p.out);
  // The first worked point of geometry_vectors.json, to its 1e-9 relative.
  EXPECT_NEAR(j["pixel"][0].get<double>(), 287.535650121873, 287.5 * 1e-9);
  EXPECT_NEAR(j["pixel"][1].get<double>(), 343.7512105053065, 343.7 * 1e-9);
  // Every digit a double needs: "287." then at least 13 more.
  const auto first = p.out.find("287.");
  ASSERT_NE(first, std::string::npos) << p.out;
  EXPECT_GE(p.out.find(',', first) - first, 17u) << "digits were cut: " << p.out;
}

TEST(GeometryCommands, BadInputGivesOneLineAndExitTwo) {
  test::TempDir dir;
  const std::string good = dir.write("good.toml", SpecCamera{}.toml());
  const std::string bad = dir.write("bad.toml", "[camera]\nNu = 1\n");
  const std::vector<std::vector<std::string>> cases = {
      {kTool, "project", bad, "1", "2", "3"},
      {kTool, "project", good, "1", "two", "3"},
      {kTool, "project", good, "1", "2"},
      {kTool, "ground", good, "1", "nan"},
      {kTool, "ground", dir.file("missing.toml"), "1", "2"},
      {kTool, "frobnicate"},
      {kTool},
  };
  for (const auto& args : cases) {
    const auto r = test::run_process(args);
    EXPECT_EQ(r.exit_status, 2) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "not one line: " << r.err;
  }
  const auto r = test::run_process({kTool, "project", bad, "1", "2", "3"});
  EXPECT_NE(r.err.find("bad.toml:2: camera.Nu"), std::string::npos) << r.err;
}

TEST(GeometryCommands, HelpExitsZero) {
  for (const char* sub : {"project", "ground"}) {
    const auto r = test::run_process({kTool, sub, "--help"});
    EXPECT_EQ(r.exit_status, 0);
    EXPECT_NE(r.out.find("config"), std::string::npos);
  }
}

}  // namespace
}  // namespace ccdlane
