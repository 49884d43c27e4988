// The example LDW consumer on a real multicast bus (a private network namespace): it
// receives lane messages and prints exactly the warning transitions, with hysteresis, a
// departure ccdlaned reports, and nothing for frames without an estimate.
#include <sys/wait.h>

#include <chrono>
#include <string>
#include <thread>

#include <ccdlane/lane_estimate_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "tests/daemon/child_process.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0";

lane_estimate_t lane(std::int64_t frame, double left_mm, std::int8_t departure = lane_estimate_t::DEPARTURE_NONE,
                     bool ok = true) {
  lane_estimate_t m{};
  m.frame = frame;
  m.ok = ok;
  m.num_lines = 3;
  m.lines[0].y0_mm = left_mm + 3600.0;  // the next lane's left line: never the nearest
  m.lines[1].y0_mm = left_mm;
  m.lines[2].y0_mm = left_mm - 3600.0;
  m.departure = departure;
  return m;
}

TEST(LdwConsumer, PrintsWarningTransitionsFromTheBus) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir dir;
  const lane_estimate_t drive[] = {
      lane(0, 1800), lane(1, 1500), lane(2, 1200),
      lane(3, 990),                                      // within 1000 mm: warning
      lane(4, 1050), lane(5, 1120),                      // still within 1000 + 150
      lane(6, 1200),                                     // beyond: clear
      lane(7, 1100),                                     // not within 1000: no chatter
      lane(8, 980),                                      // warning again
      lane(9, 3000, lane_estimate_t::DEPARTURE_NONE, false),  // no estimate: state kept
      lane(10, 1300),                                    // clear
      lane(11, 1800, lane_estimate_t::DEPARTURE_RIGHT),  // ccdlaned's verdict
      lane(12, 1800),
  };
  test::ChildProcess consumer({CCDLANE_LDW_CONSUMER, "--lcm", kUrl, "--count", "13"},
                              {{}, dir.file("out"), dir.file("err"), {}});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (test::read_file(dir.file("err")).find("listening on CCDLANE_LANES") == std::string::npos) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << test::read_file(dir.file("err"));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  lcm::LCM bus(kUrl);
  ASSERT_TRUE(bus.good());
  for (const lane_estimate_t& m : drive) {
    ASSERT_EQ(bus.publish("CCDLANE_LANES", &m), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const auto status = consumer.wait_exit(5000);
  ASSERT_TRUE(status.has_value()) << "did not receive all 13 messages:\n" << test::read_file(dir.file("out"));
  EXPECT_EQ(WEXITSTATUS(*status), 0);
  EXPECT_EQ(test::read_file(dir.file("out")),
            "frame 3: WARNING left: left line 990 mm from the vehicle centre (departure: none)\n"
            "frame 6: clear: lines 1200 mm left and 2400 mm right of the vehicle centre\n"
            "frame 8: WARNING left: left line 980 mm from the vehicle centre (departure: none)\n"
            "frame 10: clear: lines 1300 mm left and 2300 mm right of the vehicle centre\n"
            "frame 11: WARNING right: right line 1800 mm from the vehicle centre (departure: right)\n"
            "frame 12: clear: lines 1800 mm left and 1800 mm right of the vehicle centre\n");
}

}  // namespace
}  // namespace ccdlane
