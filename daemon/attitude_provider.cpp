// Names of the gyro states, as the status message and logs show them.
#include "daemon/attitude_provider.hpp"

namespace ccdlane {

const char* to_string(GyroState s) {
  switch (s) {
    case GyroState::none: return "none";
    case GyroState::starting: return "starting";
    case GyroState::ok: return "ok";
    case GyroState::stale: return "stale";
    case GyroState::lost: return "lost";
  }
  return "unknown";
}

}  // namespace ccdlane
