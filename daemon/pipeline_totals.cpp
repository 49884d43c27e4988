// Camera state names come from the status message's table.
#include "daemon/pipeline_totals.hpp"

#include "daemon/status_names.hpp"

namespace ccdlane {

const char* to_string(CameraState s) { return camera_state_name(static_cast<int>(s)); }

}  // namespace ccdlane
