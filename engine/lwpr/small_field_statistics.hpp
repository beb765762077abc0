#pragma once
// The PLS statistics of a field of 2 or 3 inputs on local values, compiled for each projection
// count: the same operations in the same order as the general field update, so the same bits.
#include "engine/lwpr/receptive_field.hpp"

#include <Eigen/Core>

namespace armfarm::lwpr {

/// What update_receptive_field() does first for a field of n = 2 or 3 inputs and R = 1..n
/// projections: the forgetting-weighted sums, β₀, the means and the PLS statistics, directions,
/// loadings and β, leaving s_r, the residuals and 1 − h_r in `scratch` (not z, which nothing reads
/// after the update). Every element is the general code's value, bit for bit: the same operations
/// in the same order, element i in partial sum i mod 4, the partial sums added as (p0 + p1) + (p2 + p3).
/// The AVX2 copy (no FMA) runs if scratch.use_avx2. Returns false, and changes nothing, for
/// another n or R.
bool update_small_field_statistics(const Eigen::VectorXd& x, double y, double w, ReceptiveField& rf,
                                   FieldScratch& scratch);

/// update_small_field_statistics() for two fields of the same n and the same sample, with their
/// own activations and scratch, in lockstep: while both have projection r, their scalar steps
/// (1/Σλw, β₀, the reductions' sum trees, √, 1/|u_r|, s_r, Σλws², its reciprocal, β, the residual,
/// 1 − h) run on pairs of doubles, field a in lane 0 and field b in lane 1. Each field ends with
/// the same bits as alone. The AVX2 copy runs if both scratches say use_avx2. Returns false, and
/// changes nothing, unless both fields qualify.
bool update_small_field_statistics_pair(const Eigen::VectorXd& x, double y, double w_a, ReceptiveField& rf_a,
                                        FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b,
                                        FieldScratch& scratch_b);

/// update_small_field_statistics_pair() for four different fields of the same n and R (rf[k] with
/// activation w[k] and its own scratch[k]): two pairs in lockstep, projection by projection, so
/// that one pair's chain through √ and the divisions overlaps the other's. Each field ends with
/// the same bits as alone. The AVX2 copy runs if every scratch says use_avx2. Returns false, and
/// changes nothing, unless all four qualify.
bool update_small_field_statistics_four(const Eigen::VectorXd& x, double y, const double* w, ReceptiveField* const* rf,
                                        FieldScratch* const* scratch);

}  // namespace armfarm::lwpr
