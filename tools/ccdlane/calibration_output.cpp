// Number formatting and atomic writes for the calibrate commands' TOML tables.
#include "tools/ccdlane/calibration_output.hpp"

#include <charconv>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace ccdlane::cli {

std::string fixed(double v, int decimals) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(decimals) << v;
  return out.str();
}

std::string scientific(double v, int decimals) {
  std::ostringstream out;
  out << std::scientific << std::setprecision(decimals) << v;
  return out.str();
}

std::string toml_float(double v) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, v).ptr;
  std::string s(buffer, end);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

}  // namespace ccdlane::cli
