// The error a configuration text gives, for the tests of the configuration's tables.
#pragma once

#include <string>

#include "app/config_loader.hpp"

namespace ccdlane::test {

// ConfigError's one line for `toml` read as `source_name`, or "(no error)".
inline std::string config_error_of(const std::string& toml, const std::string& source_name) {
  try {
    parse_config(toml, source_name);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace ccdlane::test
