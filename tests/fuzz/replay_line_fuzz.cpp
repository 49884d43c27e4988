// libFuzzer target for the replay-line reader of `ccdlane score`: no input may crash it,
// throw, or give a line with an attitude and a non-finite value. Built alone with clang
// (tools/run-tests), and replayed over its seeds by ctest.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "tests/fuzz/fuzz_check.hpp"
#include "tools/ccdlane/replay_line.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ccdlane::cli::ReplayLine line;
  const std::string why =
      ccdlane::cli::parse_replay_line(std::string_view(reinterpret_cast<const char*>(data), size), line);
  if (!why.empty() || !line.attitude) return 0;
  FUZZ_CHECK(std::isfinite(line.attitude->psi_deg) && std::isfinite(line.attitude->theta_deg) &&
             std::isfinite(line.attitude->phi_deg));
  for (const ccdlane::RoadLine& l : line.lines)
    FUZZ_CHECK(std::isfinite(l.y0_mm) && std::isfinite(l.m) && std::isfinite(l.c_per_mm));
  return 0;
}
