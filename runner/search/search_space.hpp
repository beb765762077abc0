#pragma once
// The space a search draws its trials from: one axis per swept configuration key, each uniform,
// log-uniform, integer or categorical, with inclusive bounds. Pure and I/O-free (the spec reader
// in runner/spec/ builds it from a sweep's `search` block and checks the bounds against the key
// table's range; this folder only draws and scores points).
//
// Why runner/search/ and not engine/: a search is a sequence of jobs, and the engine knows one
// job only (engine/README.md). The samplers need nothing of the runner either: the layering test
// keeps runner/search/ free of runner/execution, runner/cli, JSON, SQLite and TBB, so the same
// code is driven by the search runner and by the closed-form tests.
//
// Coordinates. A point holds one double per axis: the value itself for uniform, log-uniform and
// integer axes (an integer axis holds whole numbers), the 0-based index of the choice for a
// categorical axis. The samplers work in the *internal* coordinate z of each numeric axis:
//   uniform      z = x          on [low, high]
//   log-uniform  z = ln x       on [ln low, ln high]        (0 < low)
//   integer      z = x          on [low − ½, high + ½]      (each whole number owns a unit cell)
// so a uniform draw of z is the axis's prior, and distances in z are what "near" means.
#include <cstddef>
#include <string>
#include <vector>

#include "engine/random/random_stream.hpp"

namespace armfarm::search {

enum class AxisKind { uniform, log_uniform, integer, categorical };

/// "uniform", "log_uniform", "integer", "categorical".
const char* to_string(AxisKind kind);

/// One axis of the space.
struct SearchAxis {
  std::string path;  ///< the configuration key it sets ("lwpr.init_D")
  AxisKind kind = AxisKind::uniform;
  double low = 0.0;              ///< numeric axes: the smallest value (log-uniform: > 0)
  double high = 1.0;             ///< numeric axes: the largest value (≥ low)
  std::size_t choice_count = 0;  ///< categorical axes: how many choices (≥ 1); the spec keeps their values
};

/// The axes, in the spec's order (the order fixes the random draws).
struct SearchSpace {
  std::vector<SearchAxis> axes;
};

/// One value per axis (see "Coordinates" above).
using SearchPoint = std::vector<double>;

/// [z_low, z_high] of a numeric axis's internal coordinate.
struct InternalInterval {
  double low = 0.0;
  double high = 1.0;
};
InternalInterval calc_internal_interval(const SearchAxis& axis);
/// z of a numeric value on its axis.
double calc_internal_coordinate(const SearchAxis& axis, double value);
/// The axis value of an internal coordinate: exp for log-uniform, the nearest whole number
/// (clamped to the bounds) for integers, the bounds clamped for all.
double calc_axis_value(const SearchAxis& axis, double internal);

/// A point drawn from the prior: each axis uniform in its internal coordinate (a categorical axis
/// uniform over its choices), the axes in order from `stream`.
SearchPoint calc_random_point(const SearchSpace& space, RandomStream& stream);

/// The stream that proposes trial `trial` (0-based) of a search seeded `seed`: one stream per
/// trial, so a proposal does not depend on how many draws earlier proposals took.
RandomStream make_trial_stream(std::uint64_t seed, std::size_t trial);

}  // namespace armfarm::search
