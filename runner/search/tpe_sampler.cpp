#include "runner/search/tpe_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "runner/search/parzen_estimator.hpp"

namespace armfarm::search {
namespace {

// The good and bad estimators of one axis.
struct AxisEstimators {
  NumericParzen good_numeric;
  NumericParzen bad_numeric;
  CategoricalParzen good_categorical;
  CategoricalParzen bad_categorical;
};

std::vector<double> axis_values(const SearchAxis& axis, std::size_t index, const std::vector<const Observation*>& group) {
  std::vector<double> values;
  values.reserve(group.size());
  for (const Observation* o : group) {
    const double value = o->point[index];
    values.push_back(axis.kind == AxisKind::categorical ? value : calc_internal_coordinate(axis, value));
  }
  return values;
}

}  // namespace

std::size_t calc_tpe_startup(double full_trials) {
  constexpr double kLeast = 2.0, kMost = 10.0;
  if (!(full_trials < 4.0 * kMost)) return static_cast<std::size_t>(kMost);  // also +inf and NaN
  return static_cast<std::size_t>(std::clamp(std::ceil(full_trials / 4.0), kLeast, kMost));
}

namespace {

// The good and bad groups of the split (see "Split" in the header): the known observations and
// the liars, sorted by loss then trial, the first n_good of them good.
struct Groups {
  std::vector<const Observation*> good;
  std::vector<const Observation*> bad;          ///< known and liars, in the split's order (the per-axis rule)
  std::vector<const Observation*> bad_known;    ///< the known observations of `bad` (the joint rule's points)
  std::vector<const Observation*> bad_liars;    ///< the liars of `bad` (the joint rule's liar components)
};

Groups split_observations(const TpeSettings& settings, const std::vector<Observation>& known, const std::vector<Observation>& liars) {
  std::vector<std::pair<const Observation*, bool>> all;  // (observation, is a liar)
  for (const Observation& o : known) all.emplace_back(&o, false);
  for (const Observation& o : liars) all.emplace_back(&o, true);
  std::stable_sort(all.begin(), all.end(), [](const auto& x, const auto& y) {
    if (x.first->loss != y.first->loss) return x.first->loss < y.first->loss;
    return x.first->trial < y.first->trial;
  });
  const auto n = static_cast<double>(known.size());
  const std::size_t n_good = std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(settings.gamma * n)), 1,
                                                     std::min(settings.max_good, known.size() - 1));
  Groups groups;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (i < n_good) {
      groups.good.push_back(all[i].first);
      continue;
    }
    groups.bad.push_back(all[i].first);
    (all[i].second ? groups.bad_liars : groups.bad_known).push_back(all[i].first);
  }
  return groups;
}

// The candidate with the largest score among `candidates` draws (ties: the first drawn).
template <typename Draw>
SearchPoint find_best_candidate(const TpeSettings& settings, const Draw& draw_and_score) {
  SearchPoint best;
  double best_score = -std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < std::max<std::size_t>(settings.candidates, 1); ++c) {
    double score = 0.0;
    SearchPoint candidate = draw_and_score(score);
    if (best.empty() || score > best_score) {
      best = std::move(candidate);
      best_score = score;
    }
  }
  return best;
}

// The independent rule: per-axis estimators, the score Σ_d [ln ℓ_d(x_d) − ln g_d(x_d)].
SearchPoint propose_independent(const SearchSpace& space, const TpeSettings& settings, const Groups& groups, RandomStream& stream) {
  std::vector<AxisEstimators> estimators(space.axes.size());
  for (std::size_t d = 0; d < space.axes.size(); ++d) {
    const SearchAxis& axis = space.axes[d];
    if (axis.kind == AxisKind::categorical) {
      estimators[d].good_categorical = make_categorical_parzen(axis.choice_count, axis_values(axis, d, groups.good));
      estimators[d].bad_categorical = make_categorical_parzen(axis.choice_count, axis_values(axis, d, groups.bad));
    } else {
      estimators[d].good_numeric = make_numeric_parzen(axis, axis_values(axis, d, groups.good));
      estimators[d].bad_numeric = make_numeric_parzen(axis, axis_values(axis, d, groups.bad));
    }
  }
  return find_best_candidate(settings, [&](double& score) {
    SearchPoint candidate(space.axes.size());
    for (std::size_t d = 0; d < space.axes.size(); ++d) {
      const SearchAxis& axis = space.axes[d];
      const AxisEstimators& e = estimators[d];
      if (axis.kind == AxisKind::categorical) {
        const double choice = calc_parzen_draw(e.good_categorical, stream);
        candidate[d] = choice;
        score += calc_log_density(e.good_categorical, choice) - calc_log_density(e.bad_categorical, choice);
      } else {
        const double z = calc_parzen_draw(e.good_numeric, stream);
        candidate[d] = calc_axis_value(axis, z);
        score += calc_log_density(e.good_numeric, z) - calc_log_density(e.bad_numeric, z);
      }
    }
    return candidate;
  });
}

// The group's points in internal coordinates (categorical: the choice index).
std::vector<SearchPoint> internal_points(const SearchSpace& space, const std::vector<const Observation*>& group) {
  std::vector<SearchPoint> points;
  points.reserve(group.size());
  for (const Observation* o : group) {
    SearchPoint z(space.axes.size());
    for (std::size_t d = 0; d < space.axes.size(); ++d) {
      const SearchAxis& axis = space.axes[d];
      z[d] = axis.kind == AxisKind::categorical ? o->point[d] : calc_internal_coordinate(axis, o->point[d]);
    }
    points.push_back(std::move(z));
  }
  return points;
}

// The joint rule: one estimator over all axes per group, the liars in g with the narrower
// kernel (parzen_estimator.hpp, JointParzen), the score ln ℓ(x) − ln g(x).
SearchPoint propose_joint(const SearchSpace& space, const TpeSettings& settings, const Groups& groups, RandomStream& stream) {
  const JointParzen good = make_joint_parzen(space, internal_points(space, groups.good), settings.prior_weight, settings.bandwidth);
  JointParzen bad = make_joint_parzen(space, internal_points(space, groups.bad_known), settings.prior_weight, settings.bandwidth);
  add_joint_liars(bad, good, internal_points(space, groups.bad_liars), settings.liar_bandwidth);
  return find_best_candidate(settings, [&](double& score) {
    const SearchPoint z = calc_parzen_draw(good, stream);
    score = calc_log_density(good, z) - calc_log_density(bad, z);
    SearchPoint candidate(space.axes.size());
    for (std::size_t d = 0; d < space.axes.size(); ++d) {
      const SearchAxis& axis = space.axes[d];
      candidate[d] = axis.kind == AxisKind::categorical ? z[d] : calc_axis_value(axis, z[d]);
    }
    return candidate;
  });
}

}  // namespace

SearchPoint calc_tpe_point(const SearchSpace& space, const TpeSettings& settings, const std::vector<Observation>& known,
                           const std::vector<Observation>& pending, RandomStream& stream) {
  if (known.size() < std::max<std::size_t>(settings.startup, 2)) return calc_random_point(space, stream);
  // The liars take the worst known loss (a failed trial's +∞ included: it still sorts last).
  double worst = -std::numeric_limits<double>::infinity();
  for (const Observation& o : known) worst = std::max(worst, o.loss);
  std::vector<Observation> liars = pending;
  for (Observation& liar : liars) liar.loss = worst;
  const Groups groups = split_observations(settings, known, liars);
  return settings.joint ? propose_joint(space, settings, groups, stream) : propose_independent(space, settings, groups, stream);
}

}  // namespace armfarm::search
