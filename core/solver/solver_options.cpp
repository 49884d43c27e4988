// Names and defaults of the solver's options.
#include "core/solver/solver_options.hpp"

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

FreeSet SolverOptions::default_free() {
  FreeSet s;
  s.add(FreeParam::psi);
  s.add(FreeParam::theta);
  s.add(FreeParam::phi);
  s.add(FreeParam::y0);
  return s;
}

}  // namespace ccdlane
