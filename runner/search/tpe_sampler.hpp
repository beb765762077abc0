#pragma once
// Tree-structured Parzen estimator proposals (Bergstra et al. 2011, section 4).
//
// Joint or independent axes. The paper's TPE fits one pair of estimators per axis and multiplies
// the axes (`joint` false: NumericParzen, CategoricalParzen). The default since this session fits
// one joint estimator over all axes per group (JointParzen, parzen_estimator.hpp): the product
// kernel keeps each good point's coordinates together, and its bandwidth, a fifth of each axis for
// a lone point and narrowing as m^(−1/(D+4)), lets a handful of good points pull the proposals
// towards them. The per-axis rule's bandwidth (the larger neighbour gap, an end of the interval
// counting as a neighbour) is at least half the axis for a group of one, so with the few good
// points of a small budget (12 jobs: 1 to 3 good points) its ℓ is nearly the prior and TPE
// proposed about what random search does (runner/search/README.md has the figures).
//
// Split. The n observations (point, loss), lower loss better, are sorted by loss (ties by trial
// number, so the split is a function of the observations alone) and the first
//   n_good = min(max_good, ⌈γ · n⌉)          (γ = 0.25, max_good = 25 by default)
// form the good group, the rest the bad group. ℓ(x) is the Parzen estimator
// (parzen_estimator.hpp) of the good points, g(x) of the bad ones, per axis.
//
// Acquisition. With y* the split's loss, TPE's expected improvement is
//   EI(x) ∝ ( γ + (1 − γ) · g(x) / ℓ(x) )^(−1),
// which grows with ℓ(x)/g(x). The proposal draws `candidates` points from ℓ and keeps the one
// with the largest ln ℓ(x) − ln g(x) (per axis: Σ_d [ln ℓ_d(x_d) − ln g_d(x_d)]; ties: the first
// drawn).
//
// Parallel proposals: the constant liar (Ginsbourger, Le Riche & Carraro 2010). A trial already
// proposed whose loss is not known yet counts as an observation with the worst known loss, so it
// joins the bad group and pushes the next proposal away from where others are already looking.
// Per axis a liar is one more centre of g_d (coinciding liars get the narrowest bandwidth). In the
// joint rule a liar is a component of g of its own whose kernel is λ = 0.7 times as wide as ℓ's
// (parzen_estimator.hpp, "Liars"): with g's common bandwidth it was a bump as wide as ℓ's and
// did not move the proposal (392 of 400 within 0.05 of the pending point, 400 without liars).
// Which trials are pending is decided by the search's fixed visibility rule
// (search_schedule.hpp), never by timing.
//
// Until `startup` losses are known, proposals are prior draws (calc_random_point).
//
// Start-up and the budget. A fixed start-up of 10 (Optuna's default) is a whole search when the
// budget buys 10 trials or fewer, so a spec that does not set `tpe_startup` gets
//   startup = clamp(⌈B / 4⌉, 2, 10),   B = the budget over the cost of one job to the last rung
// (calc_tpe_startup): a quarter of what the budget buys is drawn from the prior, the rest is
// TPE's; 10 from B = 37 on. Two is the least that gives a good and a bad group.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "runner/search/search_space.hpp"

namespace armfarm::search {

struct TpeSettings {
  std::size_t startup = 10;     ///< known losses before the estimators are used
  double gamma = 0.25;          ///< γ: the fraction of observations in the good group
  std::size_t max_good = 25;    ///< at most this many good observations
  std::size_t candidates = 24;  ///< draws from ℓ scored per proposal
  bool joint = true;            ///< the joint estimators (see "Joint or independent axes"); false: per axis
  double prior_weight = 1.0;    ///< joint: w, the prior's weight beside the group's points
  double bandwidth = 0.2;       ///< joint: h, a lone point's bandwidth as a fraction of its axis
  double liar_bandwidth = 0.7;  ///< joint: λ, a liar's bandwidth as a fraction of ℓ's (parzen_estimator.hpp)
};

/// The start-up for a budget that buys `full_trials` jobs run to the last rung (see "Start-up and
/// the budget" above); full_trials may be fractional or infinite (no budget: 10).
std::size_t calc_tpe_startup(double full_trials);

/// A point and its loss (lower is better; +∞ for a failed trial).
struct Observation {
  std::size_t trial = 0;
  SearchPoint point;
  double loss = 0.0;
};

/// The proposal for trial `trial` from its stream (make_trial_stream), the known observations
/// and the points of the pending trials (the liars).
SearchPoint calc_tpe_point(const SearchSpace& space, const TpeSettings& settings, const std::vector<Observation>& known,
                           const std::vector<Observation>& pending, RandomStream& stream);

}  // namespace armfarm::search
