#include "runner/search/parzen_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace armfarm::search {
namespace {

constexpr double kInverseSqrtTwo = 0.70710678118654752440;
constexpr double kInverseSqrtTwoPi = 0.39894228040143267794;

// Draws a truncated normal by rejection. Every centre lies in [a, b] and σ ≤ b − a, so at least
// Φ(1) − Φ(0) ≈ 0.34 of the mass is inside and 200 tries fail with probability below 1e-36; the
// clamp after them only keeps the function total.
double draw_truncated_normal(double mean, double deviation, InternalInterval interval, RandomStream& stream) {
  for (int attempt = 0; attempt < 200; ++attempt) {
    const double z = stream.normal(mean, deviation);
    if (z >= interval.low && z <= interval.high) return z;
  }
  return std::clamp(mean, interval.low, interval.high);
}

}  // namespace

double calc_normal_cdf(double x) { return 0.5 * std::erfc(-x * kInverseSqrtTwo); }

NumericParzen make_numeric_parzen(const SearchAxis& axis, std::vector<double> values) {
  NumericParzen parzen;
  parzen.interval = calc_internal_interval(axis);
  parzen.integer = axis.kind == AxisKind::integer;
  std::sort(values.begin(), values.end());
  parzen.centres = values;
  const std::size_t m = values.size();
  const double width = parzen.interval.high - parzen.interval.low;
  const double smallest = width / std::min(100.0, static_cast<double>(m + 1));
  parzen.bandwidths.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    const double left = i == 0 ? parzen.interval.low : values[i - 1];
    const double right = i + 1 == m ? parzen.interval.high : values[i + 1];
    const double gap = std::max(values[i] - left, right - values[i]);
    parzen.bandwidths[i] = std::clamp(gap, smallest, width);
  }
  return parzen;
}

double calc_log_density(const NumericParzen& parzen, double z) {
  const double a = parzen.interval.low;
  const double b = parzen.interval.high;
  const double width = b - a;
  if (!(width > 0.0)) return 0.0;  // a single-value axis: every draw is that value
  const double m = static_cast<double>(parzen.centres.size());
  // The prior: density 1/(b−a), or mass 1/(b−a) for an integer cell of width 1.
  double sum = 1.0 / width;
  for (std::size_t i = 0; i < parzen.centres.size(); ++i) {
    const double mu = parzen.centres[i];
    const double sigma = parzen.bandwidths[i];
    const double mass_inside = calc_normal_cdf((b - mu) / sigma) - calc_normal_cdf((a - mu) / sigma);
    if (parzen.integer) {
      const double lo = std::max(a, z - 0.5);
      const double hi = std::min(b, z + 0.5);
      sum += (calc_normal_cdf((hi - mu) / sigma) - calc_normal_cdf((lo - mu) / sigma)) / mass_inside;
    } else {
      const double u = (z - mu) / sigma;
      sum += kInverseSqrtTwoPi * std::exp(-0.5 * u * u) / (sigma * mass_inside);
    }
  }
  return std::log(sum / (m + 1.0));
}

double calc_parzen_draw(const NumericParzen& parzen, RandomStream& stream) {
  const std::size_t component = stream.uniform_index(parzen.centres.size() + 1);
  double z = 0.0;
  if (component == parzen.centres.size()) {
    z = stream.uniform(parzen.interval.low, parzen.interval.high);
  } else {
    z = draw_truncated_normal(parzen.centres[component], parzen.bandwidths[component], parzen.interval, stream);
  }
  if (parzen.integer) {
    z = std::clamp(std::nearbyint(z), std::ceil(parzen.interval.low), std::floor(parzen.interval.high));
  }
  return z;
}

CategoricalParzen make_categorical_parzen(std::size_t choice_count, const std::vector<double>& choices) {
  CategoricalParzen parzen;
  const double k = static_cast<double>(choice_count);
  const double m = static_cast<double>(choices.size());
  std::vector<double> counts(choice_count, 0.0);
  for (double choice : choices) counts[static_cast<std::size_t>(choice)] += 1.0;
  parzen.probabilities.resize(choice_count);
  for (std::size_t c = 0; c < choice_count; ++c) parzen.probabilities[c] = (counts[c] + 1.0 / k) / (m + 1.0);
  return parzen;
}

double calc_log_density(const CategoricalParzen& parzen, double choice) {
  return std::log(parzen.probabilities[static_cast<std::size_t>(choice)]);
}

double calc_parzen_draw(const CategoricalParzen& parzen, RandomStream& stream) {
  // Inverse of the cumulative probabilities; the last choice takes any rounding remainder.
  const double u = stream.uniform();
  double cumulative = 0.0;
  for (std::size_t c = 0; c + 1 < parzen.probabilities.size(); ++c) {
    cumulative += parzen.probabilities[c];
    if (u < cumulative) return static_cast<double>(c);
  }
  return static_cast<double>(parzen.probabilities.size() - 1);
}

JointParzen make_joint_parzen(const SearchSpace& space, std::vector<SearchPoint> points, double prior_weight, double bandwidth) {
  JointParzen parzen;
  parzen.axes = space.axes;
  parzen.centres = std::move(points);
  parzen.prior_weight = prior_weight;
  const double m = static_cast<double>(std::max<std::size_t>(parzen.centres.size(), 1));
  const double d = static_cast<double>(space.axes.size());
  const double shrink = bandwidth * std::pow(m, -1.0 / (d + 4.0));  // h · m^(−1/(D+4))
  for (const SearchAxis& axis : space.axes) {
    if (axis.kind == AxisKind::categorical) {
      parzen.intervals.push_back({});
      parzen.bandwidths.push_back(std::min(1.0, shrink));
      continue;
    }
    const InternalInterval interval = calc_internal_interval(axis);
    const double width = interval.high - interval.low;
    parzen.intervals.push_back(interval);
    parzen.bandwidths.push_back(std::max(shrink * width, width / 100.0));
  }
  return parzen;
}

namespace {

// ln k_d(x_d | μ) of one axis with bandwidth h (σ_d or τ_d; categorical ε_d or ε^λ_d; see JointParzen).
double calc_log_kernel(const JointParzen& parzen, std::size_t d, double x, double mu, double h) {
  const SearchAxis& axis = parzen.axes[d];
  if (axis.kind == AxisKind::categorical) {
    const double k = static_cast<double>(axis.choice_count);
    return std::log((x == mu ? 1.0 - h : 0.0) + h / k);
  }
  const InternalInterval interval = parzen.intervals[d];
  const double mass_inside = calc_normal_cdf((interval.high - mu) / h) - calc_normal_cdf((interval.low - mu) / h);
  if (axis.kind == AxisKind::integer) {
    const double lo = std::max(interval.low, x - 0.5);
    const double hi = std::min(interval.high, x + 0.5);
    return std::log((calc_normal_cdf((hi - mu) / h) - calc_normal_cdf((lo - mu) / h)) / mass_inside);
  }
  const double u = (x - mu) / h;
  return std::log(kInverseSqrtTwoPi / (h * mass_inside)) - 0.5 * u * u;
}

// ln π(x), the prior (see JointParzen).
double calc_log_prior(const JointParzen& parzen) {
  double log_prior = 0.0;
  for (std::size_t d = 0; d < parzen.axes.size(); ++d) {
    const SearchAxis& axis = parzen.axes[d];
    const double width = axis.kind == AxisKind::categorical ? static_cast<double>(axis.choice_count)
                                                            : parzen.intervals[d].high - parzen.intervals[d].low;
    if (width > 0.0) log_prior -= std::log(width);  // a single-value axis: every draw is that value
  }
  return log_prior;
}

}  // namespace

double calc_log_density(const JointParzen& parzen, const SearchPoint& x) {
  // ln[ w·π(x) + Σ_i exp(L_i) ] − ln(m + w), with L_i = Σ_d ln k_d: summed from the largest
  // term down (log-sum-exp), since a product over many axes can underflow a double.
  std::vector<double> terms;
  terms.reserve(parzen.centres.size() + parzen.liars.size() + 1);
  terms.push_back(std::log(parzen.prior_weight) + calc_log_prior(parzen));
  const auto add_components = [&](const std::vector<SearchPoint>& centres, const std::vector<double>& bandwidths) {
    for (const SearchPoint& centre : centres) {
      double log_component = 0.0;
      for (std::size_t d = 0; d < parzen.axes.size(); ++d) {
        const bool single = parzen.axes[d].kind != AxisKind::categorical && !(parzen.intervals[d].high > parzen.intervals[d].low);
        if (!single) log_component += calc_log_kernel(parzen, d, x[d], centre[d], bandwidths[d]);
      }
      terms.push_back(log_component);
    }
  };
  add_components(parzen.centres, parzen.bandwidths);
  add_components(parzen.liars, parzen.liar_bandwidths);
  const double largest = *std::max_element(terms.begin(), terms.end());
  double sum = 0.0;
  for (double t : terms) sum += std::exp(t - largest);
  const double components = static_cast<double>(parzen.centres.size() + parzen.liars.size());
  return largest + std::log(sum) - std::log(components + parzen.prior_weight);
}

void add_joint_liars(JointParzen& bad, const JointParzen& good, std::vector<SearchPoint> liars, double fraction) {
  bad.liars = std::move(liars);
  bad.liar_bandwidths.clear();
  for (std::size_t d = 0; d < bad.axes.size(); ++d) {
    if (bad.axes[d].kind == AxisKind::categorical) {
      bad.liar_bandwidths.push_back(fraction * good.bandwidths[d]);
      continue;
    }
    const double width = bad.intervals[d].high - bad.intervals[d].low;
    bad.liar_bandwidths.push_back(std::max(fraction * good.bandwidths[d], width / 100.0));
  }
}

SearchPoint calc_parzen_draw(const JointParzen& parzen, RandomStream& stream) {
  // The component: u uniform on [0, m + w); below m it names point ⌊u⌋, above it the prior.
  // A liar is component m + j, after the points.
  const std::size_t points = parzen.centres.size();
  const double m = static_cast<double>(points + parzen.liars.size());
  const double u = stream.uniform() * (m + parzen.prior_weight);
  const bool prior = !(u < m);
  const std::size_t index = std::min(points + parzen.liars.size() - 1, static_cast<std::size_t>(u));
  const SearchPoint* centre = prior ? nullptr : index < points ? &parzen.centres[index] : &parzen.liars[index - points];
  const std::vector<double>& bandwidths = !prior && index >= points ? parzen.liar_bandwidths : parzen.bandwidths;
  SearchPoint x(parzen.axes.size());
  for (std::size_t d = 0; d < parzen.axes.size(); ++d) {
    const SearchAxis& axis = parzen.axes[d];
    if (axis.kind == AxisKind::categorical) {
      const bool keep = centre != nullptr && stream.uniform() >= bandwidths[d];
      x[d] = keep ? (*centre)[d] : static_cast<double>(stream.uniform_index(axis.choice_count));
      continue;
    }
    const InternalInterval interval = parzen.intervals[d];
    x[d] = centre == nullptr ? stream.uniform(interval.low, interval.high)
                             : draw_truncated_normal((*centre)[d], bandwidths[d], interval, stream);
    if (axis.kind == AxisKind::integer) {
      x[d] = std::clamp(std::nearbyint(x[d]), std::ceil(interval.low), std::floor(interval.high));
    }
  }
  return x;
}

}  // namespace armfarm::search
