// Video files: decoding the real 1280x720 H.264 drive (segA) to the detector's RGB input
// on one core, and encoding annotated 1280x720 frames as H.264, per frame.
#include <unistd.h>

#include <cstdio>
#include <string>

#include <benchmark/benchmark.h>

#include "base/image_buffer.hpp"
#include "drivers/frames/video_reader.hpp"
#include "drivers/frames/video_writer.hpp"

namespace ccdlane {
namespace {

const std::string kSegA = std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-drives/project_video_segA.mp4";

// Frames per second is items per second: the whole file, rewound when it ends.
void BM_DecodeH264To1280x720Rgb(benchmark::State& state) {
  VideoReader reader(kSegA);
  const ImageBuffer frame(1280, 720, PixelFormat::rgb8, 8);
  std::int64_t t = 0;
  for (auto _ : state)
    if (reader.next(frame.view(), t) != VideoRead::frame &&
        (!reader.rewind() || reader.next(frame.view(), t) != VideoRead::frame))
      state.SkipWithError(std::string(reader.problem()).c_str());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DecodeH264To1280x720Rgb)->Unit(benchmark::kMillisecond);

void BM_EncodeH264From1280x720Rgb(benchmark::State& state) {
  VideoReader reader(kSegA);
  const ImageBuffer frame(1280, 720, PixelFormat::rgb8, 8);
  std::int64_t t = 0;
  reader.next(frame.view(), t);
  const std::string out = "/tmp/ccdlane-video-bench-" + std::to_string(::getpid()) + ".mp4";
  {
    VideoWriter writer(out, {.width = 1280, .height = 720});
    std::int64_t k = 0;
    for (auto _ : state) writer.write(frame.view(), 40'000'000 * k++);
    writer.finish();
  }
  std::remove(out.c_str());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EncodeH264From1280x720Rgb)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ccdlane

BENCHMARK_MAIN();
