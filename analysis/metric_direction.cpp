#include "analysis/metric_direction.hpp"

#include <array>
#include <stdexcept>
#include <utility>

namespace armfarm {

namespace {

// Exact names. Timings depend on the machine and its load, so they are never a regression by
// default; the receptive-field count is a cost, not a quality, hence neutral.
constexpr std::array<std::pair<const char*, MetricDirection>, 12> kExactDirections{{
    {"ff_fb_ratio_avg", MetricDirection::higher_is_better},
    {"ff_fb_ratio_var", MetricDirection::lower_is_better},
    {"ff_abs_avg", MetricDirection::neutral},
    {"fb_abs_avg", MetricDirection::lower_is_better},
    {"n_receptive_fields", MetricDirection::neutral},
    {"mean_projections", MetricDirection::neutral},
    {"sim_seconds_per_wall_second", MetricDirection::ignored},
    {"learner_us_per_update", MetricDirection::ignored},
    {"learner_us_per_predict", MetricDirection::ignored},
    {"wall_seconds", MetricDirection::ignored},
    {"saturation_fraction", MetricDirection::lower_is_better},
    {"saturated_ticks", MetricDirection::lower_is_better},
}};

bool contains(const std::string& text, const char* part) { return text.find(part) != std::string::npos; }

}  // namespace

MetricDirection find_metric_direction(const std::string& metric_name) {
  for (const auto& [name, direction] : kExactDirections) {
    if (metric_name == name) return direction;
  }
  if (contains(metric_name, "nmse") || contains(metric_name, "rmse") || contains(metric_name, "error")) {
    return MetricDirection::lower_is_better;
  }
  if (contains(metric_name, "us_per_") || contains(metric_name, "seconds")) return MetricDirection::ignored;
  return MetricDirection::neutral;
}

const char* to_string(MetricDirection direction) {
  switch (direction) {
    case MetricDirection::lower_is_better: return "lower";
    case MetricDirection::higher_is_better: return "higher";
    case MetricDirection::neutral: return "neutral";
    case MetricDirection::ignored: return "ignored";
  }
  return "neutral";
}

MetricDirection parse_metric_direction(const std::string& word) {
  if (word == "lower") return MetricDirection::lower_is_better;
  if (word == "higher") return MetricDirection::higher_is_better;
  if (word == "neutral") return MetricDirection::neutral;
  if (word == "ignored") return MetricDirection::ignored;
  throw std::invalid_argument("direction must be lower, higher, neutral or ignored, not '" + word + "'");
}

}  // namespace armfarm
