#pragma once
// Closed-form objectives with known optima for the sampler tests, and a summary over seeds.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "runner/search/search_sequence.hpp"

namespace armfarm::search::testing {

constexpr double kPi = 3.14159265358979323846;

/// Branin–Hoo on x1 ∈ [−5, 10], x2 ∈ [0, 15]; global minimum 5/(4π) ≈ 0.397887 at (−π, 12.275),
/// (π, 2.275) and (9.42478, 2.475).
inline double calc_branin(double x1, double x2) {
  const double b = 5.1 / (4.0 * kPi * kPi);
  const double c = 5.0 / kPi;
  const double t = 1.0 / (8.0 * kPi);
  const double u = x2 - b * x1 * x1 + c * x1 - 6.0;
  return u * u + 10.0 * (1.0 - t) * std::cos(x1) + 10.0;
}
inline constexpr double kBraninMinimum = 0.39788735772973816;

inline SearchSpace make_branin_space() {
  SearchSpace space;
  space.axes.push_back({"x1", AxisKind::uniform, -5.0, 10.0, 0});
  space.axes.push_back({"x2", AxisKind::uniform, 0.0, 15.0, 0});
  return space;
}

/// A deterministic value in [0, 1) from a point (stands in for the noise of a short run).
inline double calc_point_noise(const SearchPoint& point) {
  std::uint64_t h = 0x9E3779B97F4A7C15ULL;
  for (double x : point) {
    std::uint64_t bits = 0;
    static_assert(sizeof bits == sizeof x);
    __builtin_memcpy(&bits, &x, sizeof bits);
    h = calc_splitmix64(h) ^ bits;
  }
  return static_cast<double>(calc_splitmix64(h) >> 11) * 0x1.0p-53;
}

/// The best loss at the last rung.
inline double calc_best_loss(const SearchSettings& settings, const SearchHistory& history) {
  const std::vector<double> best = calc_best_so_far(settings, history);
  return best.empty() ? std::numeric_limits<double>::infinity() : best.back();
}

inline double calc_median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace armfarm::search::testing
