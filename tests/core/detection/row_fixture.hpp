// One image row with exactly known bars, and the row filters run over it: the fixture of
// the row filter's tests (mark_scanner_test.cpp, dot_scanner_test.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/detection/mark_scanner.hpp"

namespace ccdlane::test {

// One row of 200 px, 3 rows tall (the scanner reads only the middle one). Bars are
// rendered by exact area coverage, so their true centre is known to any precision.
struct Row {
  std::vector<double> value = std::vector<double>(200, 80.0);
  void bar(double left, double right, double level) {  // 0-based continuous coordinates
    for (int x = 0; x < 200; ++x) {
      const double cover = std::max(0.0, std::min(x + 0.5, right) - std::max(x - 0.5, left));
      value[static_cast<std::size_t>(x)] += cover * (level - 80.0);
    }
  }
  // A camera's optics: the row convolved with a Gaussian of `sigma` pixels (its ends
  // extended).
  void blur(double sigma) {
    const int reach = static_cast<int>(std::ceil(4.0 * sigma));
    std::vector<double> out(value.size());
    for (int x = 0; x < 200; ++x) {
      double sum = 0.0, weight = 0.0;
      for (int k = -reach; k <= reach; ++k) {
        const double w = std::exp(-0.5 * k * k / (sigma * sigma));
        sum += w * value[static_cast<std::size_t>(std::clamp(x + k, 0, 199))];
        weight += w;
      }
      out[static_cast<std::size_t>(x)] = sum / weight;
    }
    value = out;
  }
  void noise(double sigma, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, sigma);
    for (double& v : value) v += n(rng);
  }
  std::vector<std::uint8_t> bytes8() const {
    std::vector<std::uint8_t> b(600);
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 200; ++x)
        b[static_cast<std::size_t>(y * 200 + x)] =
            static_cast<std::uint8_t>(std::clamp(std::lround(value[static_cast<std::size_t>(x)]), 0L, 255L));
    return b;
  }
};

inline ScanRow row_for(float mark_px) {
  ScanRow r;
  r.y = 1;
  r.mark_px = mark_px;
  r.half_width = std::max(1, static_cast<int>(std::lround(mark_px / 2)));
  r.min_width_px = std::max(0.8f, 0.4f * mark_px - 1.0f);
  r.max_width_px = 2.5f * mark_px + 2.0f;
  return r;
}

inline std::vector<MarkCandidate> scan(const std::vector<std::uint8_t>& img, const ScanRow& r, float contrast = 10) {
  MarkScanner s(200);
  std::vector<MarkCandidate> out(64);
  const int n =
      s.scan(ImageView{img.data(), 200, 3, 200, PixelFormat::mono8, 8}, r, 0, contrast, 1.0f, out.data(), 0, 64);
  out.resize(static_cast<std::size_t>(n));
  return out;
}

}  // namespace ccdlane::test
