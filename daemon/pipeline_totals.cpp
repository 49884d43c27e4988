// Names of the camera states, as the status line and logs show them.
#include "daemon/pipeline_totals.hpp"

namespace ccdlane {

const char* to_string(CameraState s) {
  switch (s) {
    case CameraState::starting: return "starting";
    case CameraState::streaming: return "streaming";
    case CameraState::stalled: return "stalled";
    case CameraState::recovering: return "recovering";
    case CameraState::ended: return "ended";
  }
  return "unknown";
}

}  // namespace ccdlane
