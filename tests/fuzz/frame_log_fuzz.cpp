// libFuzzer target for the LCM log framing that replay reads: no input may make it read
// out of bounds, allocate past its limits, loop, or lose track of a byte (every byte of
// the file is in an event returned or counted as skipped). Built alone with clang
// (tools/run-tests), and replayed over its seeds by ctest.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "bus/lcm_log_scanner.hpp"
#include "tests/fuzz/fuzz_check.hpp"

// Input: byte 0 picks the data-length limit (small limits exercise the bound), the rest
// is the log file.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::int64_t limit = data[0] & 1 ? ccdlane::kLcmLogMaxDataBytes : std::int64_t{data[0]} * 4;
  const int fd = ::memfd_create("frame_log_fuzz", MFD_CLOEXEC);
  FUZZ_CHECK(fd >= 0);
  const std::uint8_t* file = data + 1;
  const std::size_t file_size = size - 1;
  FUZZ_CHECK(::write(fd, file, file_size) == static_cast<ssize_t>(file_size));

  ccdlane::LcmLogScanner scanner(fd, limit);
  std::uint64_t in_events = 0, previous_end = 0, events = 0;
  while (scanner.next()) {
    const ccdlane::LcmLogEvent& e = scanner.event();
    FUZZ_CHECK(e.offset >= previous_end);
    FUZZ_CHECK(static_cast<std::int64_t>(e.data.size()) <= limit);
    FUZZ_CHECK(!e.channel.empty() && e.channel.size() <= static_cast<std::size_t>(ccdlane::kLcmLogMaxChannelBytes));
    const std::uint64_t bytes = ccdlane::kLcmLogHeaderBytes + e.channel.size() + e.data.size();
    FUZZ_CHECK(e.offset + bytes <= file_size);
    // What was returned is what the file holds.
    for (std::size_t i = 0; i < e.data.size(); ++i)
      FUZZ_CHECK(e.data[i] == file[e.offset + ccdlane::kLcmLogHeaderBytes + e.channel.size() + i]);
    in_events += bytes;
    previous_end = e.offset + bytes;
    FUZZ_CHECK(++events <= file_size / ccdlane::kLcmLogHeaderBytes);
  }
  FUZZ_CHECK(scanner.error().empty());
  FUZZ_CHECK(in_events + scanner.bytes_skipped() == file_size);
  FUZZ_CHECK((scanner.bytes_skipped() == 0) == (scanner.events_lost() == 0));
  FUZZ_CHECK(scanner.events_lost() >= scanner.damaged_regions());
  ::close(fd);
  return 0;
}
