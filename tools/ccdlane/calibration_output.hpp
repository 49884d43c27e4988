// What the `ccdlane calibrate` commands share: numbers as TOML and as text, and a table
// written whole or not at all.
#pragma once

#include <string>

namespace ccdlane::cli {

// A TOML float: the shortest text that reads back to the same double.
std::string toml_float(double v);
std::string fixed(double v, int decimals);
std::string scientific(double v, int decimals);

// Written under a temporary name and renamed: the file is whole or absent.
void write_atomically(const std::string& path, const std::string& text);

}  // namespace ccdlane::cli
