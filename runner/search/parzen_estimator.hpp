#pragma once
// The one-dimensional Parzen estimators of the tree-structured Parzen estimator (TPE; Bergstra,
// Bardenet, Bengio & Kégl, "Algorithms for Hyper-Parameter Optimization", NIPS 2011, section 4).
// Each estimator is built from the internal coordinates (search_space.hpp) of a group of
// observed points, on one axis.
//
// Numeric axis, group centres μ_1 ≤ … ≤ μ_m on the interval [a, b]: a mixture of the prior and
// one Gaussian per centre, each truncated to [a, b], all with equal weight 1/(m+1):
//
//   p(z) = 1/(m+1) · [ 1/(b−a)  +  Σ_i φ((z−μ_i)/σ_i) / (σ_i · Z_i) ],
//   Z_i  = Φ((b−μ_i)/σ_i) − Φ((a−μ_i)/σ_i)          (the mass of N(μ_i, σ_i²) inside [a, b]),
//
// φ, Φ the standard normal density and distribution. The bandwidth of a centre is the larger gap
// to its neighbours, the interval's ends standing in for missing neighbours (the paper's rule),
//   σ_i = max(μ_i − μ_{i−1}, μ_{i+1} − μ_i),   μ_0 = a, μ_{m+1} = b,
// clipped to [(b−a)/min(100, m+1), b−a] so that coinciding centres keep a usable width and a
// lone centre does not flatten into the prior. The prior component keeps p > 0 everywhere, so
// log p(z) is finite for every z in [a, b].
//
// Integer axis: the cell [k−½, k+½] of the whole number k carries the mixture's mass there
// (the same formula with Φ differences in place of φ, and 1/(b−a) times the cell width 1), so
// the estimator is a probability mass function over the whole numbers of the axis.
//
// Categorical axis with K choices, counts n_c of each choice in the group (Σ n_c = m): the prior
// spread evenly over the choices plus the counts,
//   p(c) = (n_c + 1/K) / (m + 1).
#include <cstddef>
#include <vector>

#include "engine/random/random_stream.hpp"
#include "runner/search/search_space.hpp"

namespace armfarm::search {

/// The estimator of one numeric axis (uniform, log-uniform or integer).
struct NumericParzen {
  InternalInterval interval;
  bool integer = false;
  std::vector<double> centres;     ///< μ_i (internal coordinates), sorted ascending
  std::vector<double> bandwidths;  ///< σ_i
};

/// The estimator of the group's internal coordinates `values` (any order) on `axis`.
NumericParzen make_numeric_parzen(const SearchAxis& axis, std::vector<double> values);
/// ln p(z) (integer axes: ln of the mass of z's cell; z is then a whole number).
double calc_log_density(const NumericParzen& parzen, double z);
/// A draw of z: a component chosen with probability 1/(m+1) each, then uniform on [a, b] (the
/// prior) or N(μ_i, σ_i²) redrawn until inside [a, b]. Integer axes round to the nearest whole number.
double calc_parzen_draw(const NumericParzen& parzen, RandomStream& stream);

/// The estimator of one categorical axis: p(c) for each choice.
struct CategoricalParzen {
  std::vector<double> probabilities;
};
CategoricalParzen make_categorical_parzen(std::size_t choice_count, const std::vector<double>& choices);
double calc_log_density(const CategoricalParzen& parzen, double choice);
double calc_parzen_draw(const CategoricalParzen& parzen, RandomStream& stream);

/// Φ(x), the standard normal distribution (through std::erfc, accurate in both tails).
double calc_normal_cdf(double x);

}  // namespace armfarm::search
