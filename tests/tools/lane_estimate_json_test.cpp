// The per-frame result's JSON: every field of docs/interfaces.md in its order, nulls for what
// a failed frame does not have, the optional sigmas.
#include "tools/ccdlane/lane_estimate_json.hpp"

#include <gtest/gtest.h>

namespace ccdlane::cli {
namespace {

LaneEstimate sample() {
  LaneEstimate e;
  e.frame = 12;
  e.t_ns = 400000000;
  e.ok = true;
  e.psi_deg = 1.05;
  e.theta_deg = 0.71;
  e.phi_deg = -2.7;
  e.H_mm = 1400.0;
  e.sigma_psi_deg = 0.04;
  e.num_lines = 2;
  e.lines[0] = {3, 1751.0, 0.0012, 0.0, 9, 0.97, 22.0, 4200.0, 38500.0};
  e.lines[1] = {4, -1850.0, 0.0012, 0.0, 11, 0.9, kUndetermined, 3900.0, 21000.0};
  e.lane_width_mm = 3601.0;
  e.lateral_offset_mm = 49.5;
  e.heading_deg = 0.07;
  e.curvature_per_m = 0.002;  // bending left, R 500 m
  e.departure = Departure::left;
  e.rms_px = 0.5;
  e.iterations = 5;
  e.latency_us = 180;
  e.state = EstimatorState::tracking;
  return e;
}

TEST(LaneEstimateJson, TheDocumentedFieldsInOrder) {
  const Json j = lane_estimate_json(sample());
  EXPECT_EQ(
      j.dump(),
      R"({"frame":12,"t_ns":400000000,"ok":true,"state":"tracking","psi_deg":1.05,"theta_deg":0.71,"phi_deg":-2.7,)"
      R"("H_mm":1400.0,"lines":[{"id":3,"y0_mm":1751.0,"m":0.0012,"c_per_mm":0.0,"marks":9,"confidence":0.97,)"
      R"("near_mm":4200.0,"far_mm":38500.0},)"
      R"({"id":4,"y0_mm":-1850.0,"m":0.0012,"c_per_mm":0.0,"marks":11,"confidence":0.9,)"
      R"("near_mm":3900.0,"far_mm":21000.0}],)"
      R"("lane_width_mm":3601.0,"lateral_offset_mm":49.5,"heading_deg":0.07,"curvature_per_m":0.002,)"
      R"("radius_of_curvature_m":500.0,"departure":"left",)"
      R"("rms_px":0.5,"iterations":5,"latency_us":180,)"
      R"("ldw":{"available":false,"reason":"no_lane","warning":"none","fired":"none","warnings":0,)"
      R"("dlc_left_mm":null,"dlc_right_mm":null,"tlc_left_s":null,"tlc_right_s":null,)"
      R"("lateral_velocity_mps":null,"speed_mps":0.0,"turn_indicator":"none","track":"lost",)"
      R"("state":{"offset_mm":null,"heading_deg":null,"curvature_per_m":null,"lane_width_mm":null,)"
      R"("pitch_deg":null,"roll_deg":null,"heading_bias_deg":null},"sigma":{"offset_mm":null,)"
      R"("heading_deg":null,"curvature_per_m":null,"lane_width_mm":null,"pitch_deg":null,"roll_deg":null,)"
      R"("heading_bias_deg":null,"lateral_velocity_mps":null}}})");
}

TEST(LaneEstimateJson, LdwObjectWithTheDocumentedNames) {
  LdwEstimate l;
  l.available = true;
  l.reason = ldw::Availability::none;
  l.warning = ldw::Side::right;
  l.fired = ldw::Side::right;
  l.warnings = 1;
  l.tracked = true;
  l.track = ldw::TrackStatus::tracking;
  l.dlc_left_mm = 1310.0;
  l.dlc_right_mm = 240.0;
  l.tlc_right_s = 0.48;
  l.lateral_velocity_mps = -0.5;
  l.speed_mps = 20.0;
  l.indicator = TurnIndicator::left;
  l.offset_mm = -420.0;
  l.heading_bias_deg = -1.4;
  l.sigma_heading_bias_deg = 0.1;
  l.sigma_roll_deg = kUndetermined;  // roll with a gyro
  const Json j = ldw_json(l);
  EXPECT_EQ(j["available"], true);
  EXPECT_EQ(j["reason"], "none");
  EXPECT_EQ(j["warning"], "right");
  EXPECT_EQ(j["dlc_left_mm"], 1310.0);
  EXPECT_EQ(j["dlc_right_mm"], 240.0);
  EXPECT_TRUE(j["tlc_left_s"].is_null()) << "not approaching the left line";
  EXPECT_EQ(j["tlc_right_s"], 0.48);
  EXPECT_EQ(j["lateral_velocity_mps"], -0.5) << "positive toward the left: this one drifts right";
  EXPECT_EQ(j["turn_indicator"], "left");
  EXPECT_EQ(j["track"], "tracking");
  EXPECT_EQ(j["state"]["offset_mm"], -420.0);
  EXPECT_EQ(j["state"]["heading_bias_deg"], -1.4) << "the mount's yaw as the heading reads it";
  EXPECT_EQ(j["sigma"]["heading_bias_deg"], 0.1);
  EXPECT_TRUE(j["sigma"]["roll_deg"].is_null());
}

TEST(LaneEstimateJson, FailedFramesSayWhyAndHaveNullsForWhatTheyLack) {
  LaneEstimate e = sample();
  e.ok = false;
  e.reason = EstimateFailure::no_lane;  // solved, but one side has no line
  e.departure = Departure::none;
  Json j = lane_estimate_json(e);
  EXPECT_EQ(j["reason"], "no_lane");
  EXPECT_EQ(j["psi_deg"], 1.05);
  EXPECT_EQ(j["lines"].size(), 2u);
  EXPECT_TRUE(j["lane_width_mm"].is_null());
  EXPECT_TRUE(j["lateral_offset_mm"].is_null());
  EXPECT_EQ(j["heading_deg"], 0.07);
  EXPECT_EQ(j["curvature_per_m"], 0.002);
  e.curvature_per_m = 0.0;  // straight: no radius
  EXPECT_EQ(lane_estimate_json(e)["curvature_per_m"], 0.0);
  EXPECT_TRUE(lane_estimate_json(e)["radius_of_curvature_m"].is_null());

  e.reason = EstimateFailure::solver_failed;
  j = lane_estimate_json(e);
  EXPECT_EQ(j["reason"], "solver_failed");
  EXPECT_TRUE(j["psi_deg"].is_null());
  EXPECT_TRUE(j["lines"].empty());
  EXPECT_TRUE(j["rms_px"].is_null());
  EXPECT_TRUE(j["curvature_per_m"].is_null());
  EXPECT_TRUE(j["radius_of_curvature_m"].is_null());
  EXPECT_EQ(j.begin().key(), "frame");
  EXPECT_EQ(std::next(j.begin(), 3).key(), "reason");  // right after ok
  EXPECT_TRUE(j["H_mm"].is_null());
  for (EstimateFailure f : {EstimateFailure::no_frame, EstimateFailure::too_few_marks, EstimateFailure::rank_deficient})
    EXPECT_EQ(lane_estimate_json(LaneEstimate{.reason = f})["reason"], to_string(f));
  // A rank-deficient frame whose solve did not converge has no height to project at.
  EXPECT_TRUE(lane_estimate_json(LaneEstimate{.reason = EstimateFailure::rank_deficient})["H_mm"].is_null());
}

TEST(LaneEstimateJson, SigmasOnRequest) {
  const Json j = lane_estimate_json(sample(), true);
  EXPECT_EQ(j["sigma"]["psi_deg"], 0.04);
  EXPECT_TRUE(j["sigma"]["theta_deg"].is_null());
  EXPECT_EQ(j["sigma"]["y0_mm"][0], 22.0);
  EXPECT_TRUE(j["sigma"]["y0_mm"][1].is_null());
  EXPECT_FALSE(lane_estimate_json(sample()).contains("sigma"));
}

}  // namespace
}  // namespace ccdlane::cli
