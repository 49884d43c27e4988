// What the `ccdlane calibrate` commands share: numbers as TOML and as text.
#pragma once

#include <string>

namespace ccdlane::cli {

// A TOML float: the shortest text that reads back to the same double.
std::string toml_float(double v);
std::string fixed(double v, int decimals);
std::string scientific(double v, int decimals);

}  // namespace ccdlane::cli
