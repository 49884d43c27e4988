// The turn indicator as a vehicle reports it (CAN gateway, frames.csv, LCM messages):
// shared vocabulary of the drivers that read it and the warning logic that heeds it.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace ccdlane {

// `both` is the hazard lights.
enum class TurnIndicator : std::uint8_t { none, left, right, both };

constexpr const char* to_string(TurnIndicator t) {  // "none", "left", "right", "both"
  switch (t) {
    case TurnIndicator::none: return "none";
    case TurnIndicator::left: return "left";
    case TurnIndicator::right: return "right";
    case TurnIndicator::both: return "both";
  }
  return "?";
}

// The name's indicator; empty for anything else.
constexpr std::optional<TurnIndicator> turn_indicator_from_string(std::string_view name) {
  for (const TurnIndicator t : {TurnIndicator::none, TurnIndicator::left, TurnIndicator::right, TurnIndicator::both})
    if (name == to_string(t)) return t;
  return std::nullopt;
}

}  // namespace ccdlane
