// Frame files: decoding a real 1280x720 frame from PNG (colour) and PGM (grey) into the
// fixed buffer, and encoding a colour frame as PNG at the writer's level, per frame.
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "drivers/frames/pgm.hpp"
#include "drivers/frames/png.hpp"

namespace ccdlane {
namespace {

const std::string kReal = std::string(CCDLANE_TEST_DATA_DIR) + "/real/";

void BM_DecodePngColour1280x720(benchmark::State& state) {
  const std::string path = kReal + "udacity-advanced-colour/000000.png";
  std::vector<std::uint8_t> pixels(1280 * 720 * 3);
  const MutableImageView into{pixels.data(), 1280, 720, 1280 * 3, PixelFormat::rgb8, 8};
  PngReader reader;
  for (auto _ : state)
    if (reader.read(path.c_str(), into) != PgmFault::none) state.SkipWithError(std::string(reader.error()).c_str());
}
BENCHMARK(BM_DecodePngColour1280x720)->Unit(benchmark::kMillisecond);

void BM_DecodePgmGrey1280x720(benchmark::State& state) {
  const std::string path = kReal + "udacity-advanced/000000.pgm";
  std::vector<std::uint8_t> pixels(1280 * 720);
  const MutableImageView into{pixels.data(), 1280, 720, 1280, PixelFormat::mono8, 8};
  PgmReader reader;
  for (auto _ : state)
    if (reader.read(path.c_str(), into) != PgmFault::none) state.SkipWithError(std::string(reader.error()).c_str());
}
BENCHMARK(BM_DecodePgmGrey1280x720)->Unit(benchmark::kMillisecond);

void BM_EncodePngColour1280x720(benchmark::State& state) {
  const OwnedPicture frame = read_png_picture(kReal + "udacity-advanced-colour/000000.png");
  const std::string out = "/tmp/ccdlane-frame-io-bench-" + std::to_string(::getpid()) + ".png";
  for (auto _ : state) write_png(out, frame.view(), static_cast<int>(state.range(0)));
  std::remove(out.c_str());
}
BENCHMARK(BM_EncodePngColour1280x720)->Arg(0)->Arg(1)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ccdlane

BENCHMARK_MAIN();
