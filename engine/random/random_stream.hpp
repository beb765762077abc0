#pragma once
// Portable pseudo-random numbers: the same seed and purpose give the same draws with every
// compiler and standard library. (The standard fixes the output of std::mt19937_64 but leaves
// the algorithms of its distributions and of std::shuffle to each library, so their numbers
// differ between libstdc++ and libc++.)
//
// Generator: xoshiro256** (Blackman & Vigna, "Scrambled linear pseudorandom number
// generators", 2018), its state filled by SplitMix64 from the seed and a hash of the purpose.
// A purpose names what the stream is for ("reaching.targets", "batch.shuffle"), so one job
// seed gives independent streams without magic salts. Uniform reals take the top 53 bits;
// integers below n are drawn by rejection (unbiased); normals by Marsaglia's polar method
// (std::sqrt is exact under IEEE 754; std::log is the one libm call).
//
// Header-only and dependency-free: the engine (jobs) and the runner (random sweeps) share it.
#include <cmath>
#include <cstdint>
#include <iterator>
#include <string_view>
#include <utility>

namespace armfarm {

/// One step of SplitMix64 (Steele, Lea & Flood 2014): advances `state` and returns a
/// well-mixed 64-bit value.
inline std::uint64_t calc_splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// 64-bit FNV-1a of a text (names a stream's purpose).
inline std::uint64_t calc_fnv1a64(std::string_view text) {
  std::uint64_t hash = 0xCBF29CE484222325ULL;
  for (char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001B3ULL;
  }
  return hash;
}

/// A stream of draws owned by one job (not thread-safe; copy it to fork a stream).
class RandomStream {
 public:
  /// The stream of `seed` for `purpose`; different purposes give unrelated streams.
  RandomStream(std::uint64_t seed, std::string_view purpose) {
    std::uint64_t mix = seed ^ calc_splitmix64_copy(calc_fnv1a64(purpose));
    for (std::uint64_t& word : state_) word = calc_splitmix64(mix);
  }

  /// A stream from a raw xoshiro256** state (for reference tests); the state must not be all zero.
  static RandomStream from_state(std::uint64_t s0, std::uint64_t s1, std::uint64_t s2, std::uint64_t s3) {
    RandomStream stream;
    stream.state_[0] = s0;
    stream.state_[1] = s1;
    stream.state_[2] = s2;
    stream.state_[3] = s3;
    return stream;
  }

  /// The next 64 random bits.
  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }

  /// Uniform in [0, 1), a multiple of 2^-53.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

  /// Uniform in [low, high).
  double uniform(double low, double high) { return low + uniform() * (high - low); }

  /// Uniform integer in [0, n), n ≥ 1, without modulo bias (rejects the top partial block).
  std::uint64_t uniform_index(std::uint64_t n) {
    const std::uint64_t threshold = (0 - n) % n;  // 2^64 mod n
    for (;;) {
      const std::uint64_t r = next_u64();
      if (r >= threshold) return r % n;
    }
  }

  /// Standard normal (mean 0, variance 1).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    for (;;) {
      const double u = 2.0 * uniform() - 1.0;
      const double v = 2.0 * uniform() - 1.0;
      const double s = u * u + v * v;
      if (s >= 1.0 || s == 0.0) continue;
      const double factor = std::sqrt(-2.0 * std::log(s) / s);
      spare_ = v * factor;
      has_spare_ = true;
      return u * factor;
    }
  }

  /// Normal with the given mean and standard deviation.
  double normal(double mean, double deviation) { return mean + deviation * normal(); }

  /// Fisher–Yates shuffle of [first, last) (random-access iterators).
  template <typename RandomIt>
  void shuffle(RandomIt first, RandomIt last) {
    const auto n = static_cast<std::uint64_t>(std::distance(first, last));
    for (std::uint64_t i = n; i > 1; --i) {
      const std::uint64_t j = uniform_index(i);
      using std::swap;
      swap(first[static_cast<std::ptrdiff_t>(i - 1)], first[static_cast<std::ptrdiff_t>(j)]);
    }
  }

 private:
  RandomStream() = default;
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t calc_splitmix64_copy(std::uint64_t value) { return calc_splitmix64(value); }

  std::uint64_t state_[4] = {};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace armfarm
