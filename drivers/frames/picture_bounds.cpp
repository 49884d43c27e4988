// The product is formed in 64 bits from sizes of at most 2^31 each: it cannot overflow.
#include "drivers/frames/picture_bounds.hpp"

namespace ccdlane {

std::string picture_size_problem(std::int64_t width, std::int64_t height, std::int64_t max_pixels) {
  if (width > 0 && height > 0 && width <= (std::int64_t{1} << 31) && height <= (std::int64_t{1} << 31) &&
      width * height <= max_pixels)
    return "";
  return std::to_string(width) + "x" + std::to_string(height) + " pixels: more than " + std::to_string(max_pixels) +
         "; not decoded";
}

}  // namespace ccdlane
