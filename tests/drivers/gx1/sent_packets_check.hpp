// Compares what a receiver decoded with what the emulator says it sent: between the
// first and the last packet received, every intact packet must have arrived, in order,
// and nothing else (no damaged packet accepted, nothing invented).
#pragma once

#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/gx1/gx1_emulator.hpp"

namespace ccdlane::gx1::test {

// A received Euler reply: the raw counts the emulator encoded.
struct ReceivedEuler {
  std::uint16_t ticks = 0;
  std::int16_t roll = 0, pitch = 0, yaw = 0;
};

inline ReceivedEuler euler_of(const Reply& r) {
  if (const auto* e = std::get_if<EulerReply>(&r)) return {e->ticks, e->roll, e->pitch, e->yaw};
  if (const auto* v = std::get_if<EulerVectorsReply>(&r)) return {v->ticks, v->roll, v->pitch, v->yaw};
  ADD_FAILURE() << "not an Euler reply";
  return {};
}

// Needs ticks that are unique over the run (EmulatorOptions::tick_seconds shorter than
// the packet period). Returns the number of intact packets matched.
inline std::size_t expect_exactly_the_intact_packets(const std::vector<ReceivedEuler>& received,
                                                     const std::vector<SentPacket>& sent) {
  if (received.empty()) {
    ADD_FAILURE() << "nothing received";
    return 0;
  }
  std::size_t s = 0;
  while (s < sent.size() && !(sent[s].intact && euler_of(sent[s].reply).ticks == received[0].ticks)) ++s;
  if (s == sent.size()) {
    ADD_FAILURE() << "the first packet received was never sent intact (ticks " << received[0].ticks << ")";
    return 0;
  }
  std::size_t matched = 0;
  for (const ReceivedEuler& r : received) {
    while (s < sent.size() && !sent[s].intact) ++s;
    if (s == sent.size()) {
      ADD_FAILURE() << "received more than was sent intact (ticks " << r.ticks << ")";
      return matched;
    }
    const ReceivedEuler e = euler_of(sent[s].reply);
    if (e.ticks != r.ticks || e.roll != r.roll || e.pitch != r.pitch || e.yaw != r.yaw) {
      ADD_FAILURE() << "packet " << sent[s].number << " (ticks " << e.ticks << ") expected, got ticks " << r.ticks
                    << ": an intact packet was lost or a damaged one accepted";
      return matched;
    }
    ++matched;
    ++s;
  }
  return matched;
}

}  // namespace ccdlane::gx1::test
