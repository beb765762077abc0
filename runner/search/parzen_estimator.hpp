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

/// The joint (multivariate) estimator of a group of m points over all D axes of a space: one
/// component per point, the product over axes of a kernel centred on the point's coordinate, beside
/// the prior with weight w (TpeSettings::prior_weight; w = 1 counts the prior as one more point):
///
///   p(x) = [ w · π(x) + Σ_i Π_d k_d(x_d | x_{i,d}) ] / (m + w),     π(x) = Π_d π_d(x_d),
///
/// π_d the axis's prior (1/(b−a) on a numeric axis's internal interval, an integer cell's mass
/// 1/(b−a), 1/K on a categorical axis of K choices). The kernels:
///   numeric     k_d(z | μ) = φ((z−μ)/σ_d) / (σ_d · Z),  Z = Φ((b−μ)/σ_d) − Φ((a−μ)/σ_d)  (truncated to [a, b]);
///   integer     the mass of z's cell [z−½, z+½] ∩ [a, b] under the same truncated normal;
///   categorical k_d(c | c_i) = (1 − ε_d) · [c = c_i] + ε_d / K.
/// One bandwidth per axis, the same for every component: Scott's rule for a product kernel in D
/// dimensions, σ = s · m^(−1/(D+4)), with the axis's width times a fixed fraction h in place of
/// the sample deviation s (which a group of one or two points does not estimate):
///   σ_d = max( h · (b−a) · m^(−1/(D+4)),  (b−a)/100 ),      ε_d = min(1, h · m^(−1/(D+4))),
/// h = TpeSettings::bandwidth (0.2). So a lone good point spreads over a fifth of its axis, not
/// over the whole of it as the per-axis rule above lets it (its larger gap is to an end of the
/// interval), and the group narrows as it grows, more slowly the more axes there are.
///
/// Why joint: the per-axis estimators multiply ℓ_1(x_1) · ℓ_2(x_2) · …, which puts mass on every
/// combination of good coordinates, also those no good point has (a good x_1 of one point with
/// the good x_2 of another). The product kernel keeps each good point's coordinates together, so
/// where one axis's best value depends on another's (init_D against update_D) the proposals
/// follow the good points themselves (Falkner, Klein & Hutter, "BOHB", ICML 2018, section 3.1,
/// use the same multivariate kernel density in place of TPE's univariate ones).
///
/// Liars (the constant liar's pending points, tpe_sampler.hpp) join g only, as components of
/// their own with a narrower kernel than the group's points:
///
///   g(x) = [ w · π(x) + Σ_i Π_d k_d(x_d | x_{i,d}; σ_d) + Σ_j Π_d k_d(x_d | p_{j,d}; τ_d) ] / (m + n_λ + w),
///   τ_d = max( λ · σ^ℓ_d, (b−a)/100 ),   categorical ε^λ_d = λ · ε^ℓ_d,
///
/// σ^ℓ_d, ε^ℓ_d the bandwidths of ℓ (the good group's estimator), λ = TpeSettings::liar_bandwidth
/// (0.7), m the known bad points (σ_d is Scott's rule over them alone; a liar is no sample of the
/// objective), n_λ the liars. Why narrower: the acquisition is ln ℓ − ln g, and the proposal is
/// drawn from ℓ. A liar with g's own width σ_d (≈ 0.76 σ^ℓ_d in the test below, both a fifth of
/// the axis shrunk by m^(−1/(D+4))) is a bump about as wide as ℓ's bump over the good point the
/// pending one was drawn near: it lowers ℓ/g over the whole bump alike and leaves its maximum
/// where it was (tpe_sampler_test's liar set-up: 392 of 400 proposals stayed within 0.05 of the
/// pending point, against 400 without liars). A liar of width τ = λ σ^ℓ has, per liar, a peak
/// density λ^(−D) · (m_ℓ + w)/(m + n_λ + w) times that of one good point's component in ℓ; near
/// the pending point p, where ℓ varies on the scale σ^ℓ, ln ℓ − ln g falls by about
/// ln(1 + L(p)/G(p)) (L the liars' part of g, G the rest of it) and recovers within
///   r ≈ τ · √(2 ln(L(p)/G(p)))
/// of p. The best of the candidates drawn from ℓ then lies about r from p, still inside ℓ's
/// bump: near the good region, not on the pending point. τ shrinks with λ and the dip deepens
/// (λ^(−D)), so λ trades exploitation for spread: on the test's set-up λ 0.5 / 0.7 / 0.8 left
/// 0 / 34 / 398 of 400 proposals within 0.05 of p (mean distance 0.144 / 0.072 / 0.017), and
/// 0.7 did best of 0.25–1.0 on the closed forms (runner/search/README.md).
struct JointParzen {
  std::vector<SearchAxis> axes;
  std::vector<InternalInterval> intervals;  ///< numeric axes: [a, b] of z; categorical: unused
  std::vector<double> bandwidths;           ///< σ_d (numeric) or ε_d (categorical)
  std::vector<SearchPoint> centres;         ///< the group's points in internal coordinates
  double prior_weight = 1.0;                ///< w
  std::vector<SearchPoint> liars;           ///< pending points (g only), internal coordinates
  std::vector<double> liar_bandwidths;      ///< τ_d (numeric) or ε^λ_d (categorical)
};

/// The joint estimator of `points` (internal coordinates: z per numeric axis, the choice index
/// per categorical axis) with prior weight w > 0 and bandwidth fraction h > 0.
JointParzen make_joint_parzen(const SearchSpace& space, std::vector<SearchPoint> points, double prior_weight, double bandwidth);
/// Adds `liars` (internal coordinates) to `bad` with the bandwidths τ_d, ε^λ_d of `good`'s scaled
/// by λ = `fraction` > 0 (see the liars above).
void add_joint_liars(JointParzen& bad, const JointParzen& good, std::vector<SearchPoint> liars, double fraction);
/// ln p(x), x in internal coordinates (integer axes: whole numbers).
double calc_log_density(const JointParzen& parzen, const SearchPoint& x);
/// A draw of x in internal coordinates: the prior with probability w/(m+n_λ+w), else component i
/// (a point, then a liar) with 1/(m+n_λ+w) each; then each axis from that component's kernel
/// (numeric: N(μ, σ_d²) redrawn until inside [a, b], integers rounded; categorical: c_i with
/// 1 − ε_d, else uniform).
SearchPoint calc_parzen_draw(const JointParzen& parzen, RandomStream& stream);

/// Φ(x), the standard normal distribution (through std::erfc, accurate in both tails).
double calc_normal_cdf(double x);

}  // namespace armfarm::search
