#pragma once
// Counter-based random numbers for the synthetic renderer: every value is a pure function
// of (seed, stream, index), so a frame renders identically whatever order or thread renders
// it, and on every platform (std::normal_distribution is implementation-defined; this is
// not). SplitMix64 finalizer (Steele, Lea, Flood 2014) as the mixing function.
#include <cmath>
#include <cstdint>

namespace bivo::odometry::synth {

inline std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

inline std::uint64_t hash3(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  return mix64(mix64(mix64(seed) ^ stream) ^ index);
}

// Uniform in the open interval (0, 1): 53 random bits, offset by half a step.
inline double uniform01(std::uint64_t bits) {
  return (static_cast<double>(bits >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

// Standard normal by Box-Muller from two independent hashes of the same counter.
inline double gaussian(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  const double u1 = uniform01(hash3(seed, stream, 2 * index));
  const double u2 = uniform01(hash3(seed, stream, 2 * index + 1));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// Per-pixel noise in the renderer's inner loop: Marsaglia's polar method on hashes of
// (key, index, attempt) gives two independent standard normals without trigonometry
// (accepts 78.5% of attempts). `key` is hash3(seed, stream, frame), computed once per frame.
struct NormalPair {
  float a, b;
};
inline NormalPair gaussian_pair(std::uint64_t key, std::uint64_t index) {
  for (std::uint64_t attempt = 0;; ++attempt) {
    const std::uint64_t bits = mix64(key ^ (index * 0xD1B54A32D192ED03ull) ^ (attempt << 58));
    const float x = static_cast<float>(bits >> 40) * (2.0f / 16777216.0f) - 1.0f;  // [-1, 1)
    const float y = static_cast<float>((bits >> 8) & 0xFFFFFFu) * (2.0f / 16777216.0f) - 1.0f;
    const float s = x * x + y * y;
    if (s >= 1.0f || s == 0.0f) continue;
    const float f = std::sqrt(-2.0f * std::log(s) / s);
    return {x * f, y * f};
  }
}

// Sequential generator for scene construction (shapes, colours): a counter over hash3.
class HashRng {
 public:
  HashRng(std::uint64_t seed, std::uint64_t stream) : seed_(seed), stream_(stream) {}
  double uniform() { return uniform01(hash3(seed_, stream_, counter_++)); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi_inclusive) { return lo + static_cast<int>(uniform() * (hi_inclusive - lo + 1)); }

 private:
  std::uint64_t seed_, stream_, counter_ = 0;
};

}  // namespace bivo::odometry::synth
