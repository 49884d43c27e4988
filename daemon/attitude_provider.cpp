// Gyro state names come from the status message's table.
#include "daemon/attitude_provider.hpp"

#include "daemon/status_names.hpp"

namespace ccdlane {

const char* to_string(GyroState s) { return gyro_state_name(static_cast<int>(s)); }

}  // namespace ccdlane
