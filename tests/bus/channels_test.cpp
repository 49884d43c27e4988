// The channel table: every channel has one row, names are prefix + suffix.
#include "bus/channels.hpp"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(Channels, NamesArePrefixPlusSuffix) {
  EXPECT_EQ(channel_name("CCDLANE_", Channel::lanes), "CCDLANE_LANES");
  EXPECT_EQ(channel_name("CCDLANE_", Channel::status), "CCDLANE_STATUS");
  EXPECT_EQ(channel_name("", Channel::lanes), "LANES");
  EXPECT_EQ(channel_name("CAR7.", Channel::status), "CAR7.STATUS");
  EXPECT_EQ(channel_name("CCDLANE_", Channel::frames), "CCDLANE_FRAMES");
  EXPECT_EQ(channel_name("CCDLANE_", Channel::vehicle), "CCDLANE_VEHICLE");
}

TEST(Channels, EveryChannelHasExactlyOneRow) {
  std::set<Channel> seen;
  std::set<std::string> suffixes;
  for (const ChannelInfo& info : kChannels) {
    EXPECT_TRUE(seen.insert(info.channel).second);
    EXPECT_TRUE(suffixes.insert(info.suffix).second) << info.suffix;
    EXPECT_EQ(&channel_info(info.channel), &info);
  }
  EXPECT_EQ(seen.size(), 4u);
}

}  // namespace
}  // namespace ccdlane
