// Small videos the tests make themselves (through the project's VideoWriter): frames whose
// content says their index, at times a test chooses, in any container and codec.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/image_buffer.hpp"
#include "drivers/frames/video_writer.hpp"

namespace ccdlane::test {

// Frame i of a test video: a diagonal gradient shifted by 7 i, so that frames differ
// everywhere and a decoder's error shows as a small difference.
void paint_test_frame(const MutableImageView& into, int index);

// Writes one frame per entry of times_ns, width x height rgb8, and returns `path`.
std::string write_test_video(const std::string& path, int width, int height, const std::vector<std::int64_t>& times_ns,
                             VideoWriterOptions options = {});

// The largest difference of any byte between two images of one size and format.
int max_abs_difference(const ImageView& a, const ImageView& b);
// The mean difference of the bytes: what a lossy codec's error is judged by.
double mean_abs_difference(const ImageView& a, const ImageView& b);

}  // namespace ccdlane::test
