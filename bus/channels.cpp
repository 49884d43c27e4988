// Channel names from the table in channels.hpp.
#include "bus/channels.hpp"

namespace ccdlane {

const ChannelInfo& channel_info(Channel c) {
  for (const ChannelInfo& info : kChannels)
    if (info.channel == c) return info;
  return kChannels[0];  // unreachable: every enumerator has a row (checked by the test)
}

std::string channel_name(std::string_view prefix, Channel c) {
  std::string name(prefix);
  name += channel_info(c).suffix;
  return name;
}

}  // namespace ccdlane
