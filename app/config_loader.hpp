// Loading and validating a ccdlane TOML configuration, once, at start-up.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "app/config.hpp"

namespace ccdlane {

// A configuration that cannot be used. what() is one line naming the file, the line and
// the key ("ccdlane.toml:12: camera.Nu: must be at least 2, got 1").
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Limits on what a configuration may ask for, checked at load: a picture side (frames
// are allocated from [camera] Nu x Nv), and the size of the file itself.
inline constexpr int kMaxImageSide = 8192;
inline constexpr std::size_t kMaxConfigBytes = std::size_t{1} << 20;
inline constexpr std::size_t kMaxInstanceChars = 64;  // [lcm] instance

// Parses TOML text; `source_name` names it in error messages.
Config parse_config(std::string_view toml_text, const std::string& source_name);

// Every key parse_config() accepts, as "table.key" ("camera.Nu", "lines.y0_mm" for the
// keys of each [[lines]] table), table by table.
std::vector<std::string> config_keys();

// Reads and parses a file. Throws ConfigError (also for a file that cannot be read: the
// reason from the system, "is a directory", or more than kMaxConfigBytes).
Config load_config_file(const std::string& path);

}  // namespace ccdlane
