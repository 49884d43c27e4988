// The example LDW consumer on a real multicast bus (a private network namespace): it
// receives lane messages and prints exactly ccdlaned's LDW transitions: availability
// with its reason, each warning as it fires (side, DLC, TLC), and its clearing; no
// threshold of its own (a line near the vehicle without a warning prints nothing).
#include <sys/wait.h>

#include <chrono>
#include <cmath>
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

lane_estimate_t lane(std::int64_t frame, std::int8_t reason, std::int8_t warning = lane_estimate_t::WARNING_NONE,
                     std::int8_t fired = lane_estimate_t::WARNING_NONE) {
  lane_estimate_t m{};
  m.frame = frame;
  m.ok = true;
  m.num_lines = 2;
  m.lines[0].y0_mm = 500.0;  // a line very near: the consumer has no threshold of its own
  m.lines[1].y0_mm = -3200.0;
  m.ldw_available = reason == lane_estimate_t::LDW_REASON_NONE;
  m.ldw_reason = reason;
  m.ldw_warning = warning;
  m.ldw_fired = fired;
  m.dlc_left_mm = 240.0;
  m.dlc_right_mm = 1500.0;
  m.tlc_left_s = 0.48;
  m.tlc_right_s = NAN;
  m.lateral_velocity_mps = 0.5;
  return m;
}

TEST(LdwConsumer, PrintsWarningTransitionsFromTheBus) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir dir;
  constexpr std::int8_t kOk = lane_estimate_t::LDW_REASON_NONE, kLeft = lane_estimate_t::WARNING_LEFT,
                        kRight = lane_estimate_t::WARNING_RIGHT;
  const lane_estimate_t drive[] = {
      lane(0, lane_estimate_t::LDW_REASON_TOO_SLOW),  // unavailable from the start
      lane(1, lane_estimate_t::LDW_REASON_TOO_SLOW),
      lane(2, lane_estimate_t::LDW_REASON_NO_LANE),  // another reason
      lane(3, kOk),                                  // available
      lane(4, kOk),
      lane(5, kOk, kLeft, kLeft),  // the warning fires
      lane(6, kOk, kLeft),         // and stays set
      lane(7, kOk),                // clear
      lane(8, kOk),
      lane(9, kOk, kRight, kRight),                      // another departure
      lane(10, lane_estimate_t::LDW_REASON_GYRO_FAULT),  // clear and unavailable
      lane(11, lane_estimate_t::LDW_REASON_GYRO_FAULT),
      lane(12, kOk),
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
            "frame 0: LDW unavailable: too slow\n"
            "frame 2: LDW unavailable: no lane\n"
            "frame 3: LDW available\n"
            "frame 5: WARNING left: wheel 240 mm from the line, crossing in 0.48 s (lateral 0.50 m/s)\n"
            "frame 7: clear\n"
            "frame 9: WARNING right: wheel 1500 mm from the line (lateral 0.50 m/s)\n"
            "frame 10: LDW unavailable: gyro fault\n"
            "frame 10: clear\n"
            "frame 12: LDW available\n");
}

}  // namespace
}  // namespace ccdlane
