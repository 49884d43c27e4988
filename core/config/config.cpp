// Defaults and small helpers of the configuration schema.
#include "core/config/config.hpp"

namespace ccdlane {
namespace {
constexpr const char* kFreeParamNames[kFreeParamCount] = {"psi", "theta", "phi", "H", "f", "y0", "m", "c"};
}

const char* free_param_name(FreeParam p) { return kFreeParamNames[static_cast<int>(p)]; }

std::optional<FreeParam> free_param_from_name(const std::string& name) {
  for (int i = 0; i < kFreeParamCount; ++i)
    if (name == kFreeParamNames[i]) return static_cast<FreeParam>(i);
  return std::nullopt;
}

FreeSet SolverConfig::default_free() {
  FreeSet s;
  s.add(FreeParam::psi);
  s.add(FreeParam::theta);
  s.add(FreeParam::phi);
  s.add(FreeParam::y0);
  return s;
}

CameraPose Config::nominal_pose() const {
  CameraPose pose;
  pose.attitude = {deg_to_rad(attitude.psi_deg), deg_to_rad(attitude.theta_deg), deg_to_rad(attitude.phi_deg)};
  pose.H_mm = H_mm;
  pose.f_mm = f_mm;
  return pose;
}

Config default_config() {
  Config c;
  c.camera = CameraSpec{};
  c.camera.k_px2 = -8.3042e-7;
  c.camera.yM_mm = -27.25;
  c.camera.zM_mm = 2.53;
  return c;
}

}  // namespace ccdlane
