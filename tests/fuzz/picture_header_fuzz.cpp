// libFuzzer target for the picture headers tools read whole and frames are read by: the
// PGM/PPM header parser over the bytes, and the PNG reader (libpng) over the same bytes as
// a file. No input may crash them, read out of bounds, or give a header that says
// nonsense; a picture is decoded whole only within the tools' bound, so no small input
// makes a huge allocation. Built alone with clang (tools/run-tests), replayed over its
// seeds by ctest.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "drivers/frames/pgm.hpp"
#include "drivers/frames/picture_bounds.hpp"
#include "drivers/frames/png.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

void check_pgm(std::string_view bytes) {
  ccdlane::PgmHeader h;
  if (ccdlane::parse_pgm_header(bytes, h) != ccdlane::PgmFault::none) return;
  FUZZ_CHECK(h.width >= 1 && h.width <= 65535 && h.height >= 1 && h.height <= 65535);
  FUZZ_CHECK(h.maxval >= 1 && h.maxval <= 65535);
  FUZZ_CHECK(h.channels == 1 || (h.channels == 3 && h.maxval <= 255));
  FUZZ_CHECK(h.offset <= bytes.size());
}

// Whole pictures only where they are small, so that the fuzzer stays fast; the bound's
// own check is what the tools do first.
constexpr std::int64_t kFuzzMaxPixels = 1 << 20;

void check_png(const std::uint8_t* data, std::size_t size) {
  const int fd = ::memfd_create("picture_header_fuzz", MFD_CLOEXEC);
  FUZZ_CHECK(fd >= 0);
  FUZZ_CHECK(::write(fd, data, size) == static_cast<ssize_t>(size));
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  ccdlane::PngReader reader;
  ccdlane::PgmHeader h;
  if (reader.probe(path.c_str(), h) == ccdlane::PgmFault::none) {
    FUZZ_CHECK(h.width >= 1 && h.height >= 1);
    FUZZ_CHECK(h.channels == 1 || h.channels == 3);
    if (ccdlane::picture_size_problem(h.width, h.height, kFuzzMaxPixels).empty()) {
      try {
        const ccdlane::OwnedPicture p = ccdlane::read_png_picture(path);
        FUZZ_CHECK(p.width == h.width && p.height == h.height);
      } catch (const std::runtime_error&) {  // damaged past the header: named, not a crash
      }
    }
  }
  ::close(fd);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  check_pgm(std::string_view(reinterpret_cast<const char*>(data), size));
  check_png(data, size);
  return 0;
}
