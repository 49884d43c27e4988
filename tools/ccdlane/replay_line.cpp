// nlohmann::json is parsed without exceptions and read only through checked accessors:
// operator[] on a missing key of a const object is undefined behaviour there.
#include "tools/ccdlane/replay_line.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

namespace ccdlane::cli {
namespace {

using Json = nlohmann::json;

// A finite number at `key` of `object` into `out`, else false.
bool number_at(const Json& object, const char* key, double& out) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return false;
  out = it->get<double>();
  return std::isfinite(out);
}

}  // namespace

std::string parse_replay_line(std::string_view text, ReplayLine& out) {
  const Json e = Json::parse(text, nullptr, false);
  if (e.is_discarded() || !e.is_object()) return "not a JSON object";
  const auto frame = e.find("frame");
  if (frame == e.end() || !frame->is_number_unsigned()) return "frame: not a frame number";
  out = ReplayLine{};
  out.frame = frame->get<std::uint64_t>();
  const auto psi = e.find("psi_deg");
  if (psi == e.end() || psi->is_null()) return "";  // not solved: nothing more to read
  ReplayAttitude a;
  if (!number_at(e, "psi_deg", a.psi_deg)) return "psi_deg: not a number";
  if (!number_at(e, "theta_deg", a.theta_deg)) return "theta_deg: not a number";
  if (!number_at(e, "phi_deg", a.phi_deg)) return "phi_deg: not a number";
  if (const auto h = e.find("H_mm"); h != e.end() && !h->is_null()) {
    double H = 0.0;
    if (!number_at(e, "H_mm", H) || !(H > 0.0)) return "H_mm: not a height";
    a.H_mm = H;
  }
  out.attitude = a;
  const auto lines = e.find("lines");
  if (lines == e.end()) return "";
  if (!lines->is_array()) return "lines: not an array";
  for (std::size_t i = 0; i < lines->size(); ++i) {
    const Json& l = (*lines)[i];
    const std::string at = "lines[" + std::to_string(i) + "]";
    if (!l.is_object()) return at + ": not an object";
    RoadLine p;
    if (!number_at(l, "y0_mm", p.y0_mm)) return at + ".y0_mm: not a number";
    if (!number_at(l, "m", p.m)) return at + ".m: not a number";
    if (!number_at(l, "c_per_mm", p.c_per_mm)) return at + ".c_per_mm: not a number";
    std::optional<double> near;
    if (const auto n = l.find("near_mm"); n != l.end() && !n->is_null()) {
      double mm = 0.0;
      if (!number_at(l, "near_mm", mm) || !(mm > 0.0)) return at + ".near_mm: not a distance";
      near = mm;
    }
    out.lines.push_back(p);
    out.near_mm.push_back(near);
  }
  return "";
}

}  // namespace ccdlane::cli
