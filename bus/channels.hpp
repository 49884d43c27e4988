// The one table of ccdlane's LCM channels: name suffix (after the configurable prefix,
// default "CCDLANE_"), message type and what each carries.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace ccdlane {

enum class Channel : std::uint8_t { lanes, status, frames, vehicle };

struct ChannelInfo {
  Channel channel;
  const char* suffix;   // the name is prefix + suffix: "CCDLANE_LANES"
  const char* type;     // the LCM type on it
  const char* carries;  // for help texts and logs
};

inline constexpr ChannelInfo kChannels[] = {
    {Channel::lanes, "LANES", "ccdlane.lane_estimate_t", "one lane estimate per processed frame"},
    {Channel::status, "STATUS", "ccdlane.status_t", "daemon health, once per second"},
    {Channel::frames, "FRAMES", "ccdlane.frame_t", "raw frames, when recording ([lcm] publish_frames, ccdlane record)"},
    {Channel::vehicle, "VEHICLE", "ccdlane.vehicle_state_t",
     "the vehicle's speed, yaw rate and turn indicator, from a CAN gateway (ccdlaned subscribes)"},
};

const ChannelInfo& channel_info(Channel c);

// The full channel name. Allocates: build names once, at start-up.
std::string channel_name(std::string_view prefix, Channel c);

}  // namespace ccdlane
