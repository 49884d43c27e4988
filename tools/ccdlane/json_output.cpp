// JSON helpers. nlohmann prints doubles with the shortest form that reads back to the
// same value, which is the "full precision" the interfaces ask for.
#include "tools/ccdlane/json_output.hpp"

#include <cmath>
#include <ostream>

namespace ccdlane::cli {

Json json_number(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

Json json_array(const std::optional<Vec2>& v) {
  if (!v) return Json(nullptr);
  return Json::array({json_number(v->x()), json_number(v->y())});
}

Json json_array(const std::optional<Vec3>& v) {
  if (!v) return Json(nullptr);
  return Json::array({json_number(v->x()), json_number(v->y()), json_number(v->z())});
}

void print_json_line(std::ostream& out, const Json& j) { out << j.dump() << '\n'; }

}  // namespace ccdlane::cli
