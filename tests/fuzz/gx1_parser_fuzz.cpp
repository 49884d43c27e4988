// libFuzzer target for the 3DM-GX1 reply parser: no input may make it read out of
// bounds, stall, lose track of a byte, or accept a reply that is not in the input.
// Built alone with clang (tools/run-tests), and replayed over its seeds by ctest.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "drivers/gx1/gx1_protocol.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using namespace ccdlane::gx1;

void expect_set(ReplyParser& parser, unsigned choice) {
  switch (choice) {
    case 1:  // streaming 0x0E
      parser.expect({cmd::continuous, cmd::stab_euler});
      break;
    case 2:  // streaming 0x31
      parser.expect({cmd::continuous, cmd::stab_euler_vectors});
      break;
    case 3:  // configuration replies
      parser.expect({cmd::firmware, cmd::serial_number, cmd::read_eeprom, cmd::temperature, cmd::stab_quaternion});
      break;
    default: parser.expect_default(); break;
  }
}

}  // namespace

// Input: byte 0 picks the parser options, byte 1 the chunk size; the rest is the stream.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  ReplyParser parser;
  parser.confirm_resync(data[0] & 1);
  expect_set(parser, (data[0] >> 1) & 3);
  const std::size_t chunk = 1 + data[1] % 40;
  const std::uint8_t* stream = data + 2;
  const std::size_t length = size - 2;

  std::size_t fed = 0;
  std::uint64_t in_replies = 0, replies = 0, last_end = 0;
  ParsedReply reply;
  while (fed < length) {
    std::span<const std::uint8_t> piece(stream + fed, std::min(chunk, length - fed));
    while (!piece.empty()) {
      const std::size_t took = parser.feed(piece);
      FUZZ_CHECK(took > 0);  // never stalls: after next() said "need more", more fits
      piece = piece.subspan(took);
      fed += took;
      while (parser.next(reply)) {
        const Frame frame = encode_reply(reply.reply);
        FUZZ_CHECK(frame.size == reply_length(frame.bytes[0]));
        FUZZ_CHECK(reply.end_offset <= fed && reply.end_offset >= last_end + frame.size);
        // The reply is exactly the input bytes where it was found, checksum included.
        FUZZ_CHECK(std::memcmp(stream + reply.end_offset - frame.size, frame.bytes.data(), frame.size) == 0);
        last_end = reply.end_offset;
        in_replies += frame.size;
        ++replies;
      }
      FUZZ_CHECK(parser.buffered() <= kMaxReplyLength);
    }
  }
  const ParserCounters& c = parser.counters();
  FUZZ_CHECK(c.bytes_fed == length);
  FUZZ_CHECK(c.replies == replies);
  FUZZ_CHECK(in_replies + c.bytes_skipped + parser.buffered() == length);  // every byte accounted for
  return 0;
}
