// LaneEstimate -> JSON.
#include "tools/ccdlane/lane_estimate_json.hpp"

namespace ccdlane::cli {

Json ldw_json(const LdwEstimate& l) {
  const Json null(nullptr);
  const auto tlc = [&](const std::optional<double>& t) { return t ? json_number(*t) : null; };
  const auto tracked = [&](double v) { return l.tracked ? json_number(v) : null; };
  Json j;
  j["available"] = l.available;
  j["reason"] = to_string(l.reason);
  j["warning"] = to_string(l.warning);
  j["fired"] = to_string(l.fired);
  j["warnings"] = l.warnings;
  j["dlc_left_mm"] = tracked(l.dlc_left_mm);
  j["dlc_right_mm"] = tracked(l.dlc_right_mm);
  j["tlc_left_s"] = tlc(l.tlc_left_s);
  j["tlc_right_s"] = tlc(l.tlc_right_s);
  j["lateral_velocity_mps"] = tracked(l.lateral_velocity_mps);
  j["speed_mps"] = json_number(l.speed_mps);
  j["turn_indicator"] = to_string(l.indicator);
  j["track"] = to_string(l.track);
  j["state"] = Json{{"offset_mm", tracked(l.offset_mm)},
                    {"heading_deg", tracked(l.heading_deg)},
                    {"curvature_per_m", tracked(l.curvature_per_m)},
                    {"lane_width_mm", tracked(l.lane_width_mm)},
                    {"pitch_deg", tracked(l.pitch_deg)},
                    {"roll_deg", tracked(l.roll_deg)},
                    {"heading_bias_deg", tracked(l.heading_bias_deg)}};
  j["sigma"] = Json{{"offset_mm", tracked(l.sigma_offset_mm)},
                    {"heading_deg", tracked(l.sigma_heading_deg)},
                    {"curvature_per_m", tracked(l.sigma_curvature_per_m)},
                    {"lane_width_mm", tracked(l.sigma_lane_width_mm)},
                    {"pitch_deg", tracked(l.sigma_pitch_deg)},
                    {"roll_deg", tracked(l.sigma_roll_deg)},
                    {"heading_bias_deg", tracked(l.sigma_heading_bias_deg)},
                    {"lateral_velocity_mps", tracked(l.sigma_lateral_velocity_mps)}};
  return j;
}

Json lane_estimate_json(const LaneEstimate& e, bool sigmas) {
  // What exists depends on how far the frame got.
  const bool solved = e.ok || e.reason == EstimateFailure::no_lane || e.reason == EstimateFailure::rank_deficient;
  const Json null(nullptr);
  Json j;
  j["frame"] = e.frame;
  j["t_ns"] = e.t_ns;
  j["ok"] = e.ok;
  if (!e.ok) j["reason"] = to_string(e.reason);
  if (e.support != SupportProblem::none) j["support"] = to_string(e.support);
  j["state"] = to_string(e.state);
  j["psi_deg"] = solved ? json_number(e.psi_deg) : null;
  j["theta_deg"] = solved ? json_number(e.theta_deg) : null;
  j["phi_deg"] = solved ? json_number(e.phi_deg) : null;
  j["H_mm"] = solved && e.H_mm > 0.0 ? json_number(e.H_mm) : null;  // 0: no solve gave one
  Json lines = Json::array();
  for (int k = 0; solved && k < e.num_lines; ++k) {
    const EstimatedLine& l = e.lines[static_cast<std::size_t>(k)];
    lines.push_back(Json{{"id", l.id},
                         {"y0_mm", json_number(l.y0_mm)},
                         {"m", json_number(l.m)},
                         {"c_per_mm", json_number(l.c_per_mm)},
                         {"marks", l.marks},
                         {"confidence", json_number(l.confidence)},
                         {"near_mm", json_number(l.near_mm)},
                         {"far_mm", json_number(l.far_mm)}});
  }
  j["lines"] = std::move(lines);
  j["lane_width_mm"] = e.ok ? json_number(e.lane_width_mm) : null;
  j["lateral_offset_mm"] = e.ok ? json_number(e.lateral_offset_mm) : null;
  j["heading_deg"] = solved ? json_number(e.heading_deg) : null;
  j["curvature_per_m"] = solved ? json_number(e.curvature_per_m) : null;
  j["radius_of_curvature_m"] = solved && e.curvature_per_m != 0.0 ? json_number(1.0 / e.curvature_per_m) : null;
  j["departure"] = to_string(e.departure);
  j["rms_px"] = solved ? json_number(e.rms_px) : null;
  j["iterations"] = e.iterations;
  j["latency_us"] = e.latency_us;
  if (sigmas) {
    Json y0 = Json::array();
    for (int k = 0; solved && k < e.num_lines; ++k)
      y0.push_back(json_number(e.lines[static_cast<std::size_t>(k)].sigma_y0_mm));
    j["sigma"] = Json{{"psi_deg", solved ? json_number(e.sigma_psi_deg) : null},
                      {"theta_deg", solved ? json_number(e.sigma_theta_deg) : null},
                      {"phi_deg", solved ? json_number(e.sigma_phi_deg) : null},
                      {"y0_mm", std::move(y0)}};
  }
  j["ldw"] = ldw_json(e.ldw);
  return j;
}

}  // namespace ccdlane::cli
