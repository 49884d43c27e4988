// JSON Lines as the tools write them (replay's estimates, `ccdlane score --json`'s
// callers): one object per non-empty line.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ccdlane::test {

inline std::vector<nlohmann::json> json_lines(const std::string& text) {
  std::vector<nlohmann::json> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

// Replay's JSON Lines less each frame's latency: the one field two runs of the same
// replay differ in (their clocks).
inline std::vector<nlohmann::json> json_lines_without_latency(const std::string& text) {
  std::vector<nlohmann::json> out = json_lines(text);
  for (nlohmann::json& e : out) e.erase("latency_us");
  return out;
}

}  // namespace ccdlane::test
