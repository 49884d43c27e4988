// Loads tests/data/geometry_vectors.json: the worked numbers of docs/geometry.md.
#pragma once

#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geometry/camera_model.hpp"

namespace ccdlane::test {

struct GeometryCase {
  CameraSpec spec;
  CameraPose pose;
  nlohmann::json raw;  // the case as written, for the expected values
};

inline std::vector<GeometryCase> load_geometry_vectors() {
  const std::string path = std::string(CCDLANE_TEST_DATA_DIR) + "/geometry_vectors.json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  const nlohmann::json doc = nlohmann::json::parse(in);
  const auto& cam = doc.at("camera");
  std::vector<GeometryCase> cases;
  for (const auto& c : doc.at("cases")) {
    GeometryCase g;
    g.spec.U_mm = cam.at("U_mm");
    g.spec.V_mm = cam.at("V_mm");
    g.spec.Uc_mm = cam.at("Uc_mm");
    g.spec.Vc_mm = cam.at("Vc_mm");
    g.spec.Nu = cam.at("Nu");
    g.spec.Nv = cam.at("Nv");
    g.spec.yM_mm = cam.at("yM_mm");
    g.spec.zM_mm = cam.at("zM_mm");
    g.spec.cx = c.at("cx");
    g.spec.cy = c.at("cy");
    g.spec.k_px2 = c.at("k_px2");
    g.pose.attitude = {deg_to_rad(c.at("psi_deg")), deg_to_rad(c.at("theta_deg")), deg_to_rad(c.at("phi_deg"))};
    g.pose.H_mm = c.at("H_mm");
    g.pose.f_mm = c.at("f_mm");
    g.raw = c;
    cases.push_back(g);
  }
  return cases;
}

}  // namespace ccdlane::test
