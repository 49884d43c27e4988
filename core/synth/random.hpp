// Deterministic, stateless randomness for the synthetic road: the same seed gives the
// same frames on every machine (no std:: distributions, whose output is unspecified).
#pragma once

#include <cmath>
#include <cstdint>

namespace ccdlane::synth {

// SplitMix64's finaliser: a strong 64-bit mix of its input.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

constexpr std::uint64_t hash(std::uint64_t a, std::uint64_t b) { return mix64(a ^ mix64(b)); }
constexpr std::uint64_t hash(std::uint64_t a, std::uint64_t b, std::uint64_t c) { return hash(hash(a, b), c); }

// Uniform in [0, 1) from the top 53 bits.
constexpr double unit(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

// A standard normal sample from two hashed uniforms (Box-Muller).
inline double normal(std::uint64_t bits) {
  const double u1 = 1.0 - unit(bits);  // (0, 1]
  const double u2 = unit(mix64(bits));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// xorshift64*: a fast sequential generator for per-pixel sensor noise.
class PixelNoise {
 public:
  explicit PixelNoise(std::uint64_t seed) : state_(mix64(seed) | 1u) {}
  std::uint64_t next() {
    state_ ^= state_ >> 12;
    state_ ^= state_ << 25;
    state_ ^= state_ >> 27;
    return state_ * 0x2545F4914F6CDD1Dull;
  }

 private:
  std::uint64_t state_;
};

}  // namespace ccdlane::synth
