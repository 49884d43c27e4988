// JSON printing for the tools: full double precision, null for what has no answer.
#pragma once

#include <iosfwd>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/geometry/types.hpp"

namespace ccdlane::cli {

using Json = nlohmann::ordered_json;

// A finite double as a JSON number, anything else as null.
Json json_number(double v);
Json json_array(const std::optional<Vec2>& v);
Json json_array(const std::optional<Vec3>& v);

// One JSON object per line; numbers keep every digit needed to read back exactly.
void print_json_line(std::ostream& out, const Json& j);

}  // namespace ccdlane::cli
