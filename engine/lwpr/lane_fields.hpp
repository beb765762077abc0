#pragma once
// Receptive fields stored one vector lane per output. Without update_D every output of a model holds
// the same fields: the same centre, metric, λ, x₀, sample counts and trust flag (LwprModel,
// shared_scan_). Only the local regressions differ. A LaneField keeps the shared part once and the
// outputs' regressions side by side, output o's value of every statistic in lane o % kOutputLanes
// of block o / kOutputLanes, so that one vector operation updates or evaluates one field for
// kOutputLanes outputs. Each lane runs exactly the operations of update_receptive_field() and
// predict_receptive_field() on its output's copy of the field, in the same order, so every number
// is the same bits as the per-output representation's. Normalised units (receptive_field.hpp).
#include "engine/lwpr/lwpr_params.hpp"
#include "engine/lwpr/receptive_field.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace armfarm::lwpr {

/// Outputs per lane block (one AVX-512 vector of doubles, two AVX2 ones, four SSE2 ones).
constexpr int kOutputLanes = 8;

/// The regressions of up to kOutputLanes outputs' copies of one field. Lanes past the model's
/// outputs are padding: n_reg 0 and every value 0. Statistics of projection r are at
/// [r·kOutputLanes + l]; element i of a projection's n-vector at [(r·n + i)·kOutputLanes + l]. Each
/// array holds max_reg projections; projections r ≥ n_reg[l] of lane l hold zeros.
struct LaneBlock {
  int n_reg[kOutputLanes] = {};            ///< projections of lane l's output (0: padding)
  double n_reg_lanes[kOutputLanes] = {};   ///< n_reg as doubles (the kernels' lane masks)
  int max_reg = 0;                         ///< the largest n_reg: the projections every array holds
  double beta0[kOutputLanes] = {};         ///< β₀ per lane
  double sum_e2[kOutputLanes] = {};        ///< Σλw e² per lane (stays as restored without update_D)
  double press_E[kOutputLanes] = {};       ///< PRESS sum per lane (likewise)
  std::vector<double> sum_w, n_data, ss2, sys, beta, sum_e_cv2, press_H, press_R;  ///< max_reg·kOutputLanes
  std::vector<double> sxy, sxs, directions, loadings;  ///< max_reg·n·kOutputLanes
};

/// One field of every output: the shared part once, the regressions in lane blocks.
struct LaneField {
  Eigen::VectorXd center;          ///< c (n)
  Eigen::MatrixXd metric_factor;   ///< M (as ReceptiveField)
  Eigen::MatrixXd metric;          ///< D
  Eigen::MatrixXd log_alpha;       ///< (never changed without update_D)
  Eigen::MatrixXd meta_trace;      ///< (likewise)
  double lambda = 0.999;           ///< forgetting factor, the same for every output
  Eigen::VectorXd mean_x;          ///< x₀ (n), the same for every output
  bool trustworthy = false;        ///< n_data(0) ≥ trust_n_data, the same for every output
  int n_out = 0;                   ///< outputs (lanes in use over all blocks)
  std::vector<LaneBlock> blocks;   ///< ⌈n_out / kOutputLanes⌉

  int input_dim() const { return static_cast<int>(center.size()); }
  /// Projections of output o's copy.
  int n_reg(int output) const { return blocks[output / kOutputLanes].n_reg[output % kOutputLanes]; }
};

/// Scratch of the lane update and prediction (sized once by resize(), reused; no allocation per call).
struct LaneScratch {
  std::vector<double> z;            ///< input residual per lane (n·kOutputLanes)
  std::vector<double> s;            ///< projections per lane (n·kOutputLanes)
  std::vector<double> residual;     ///< output residual after each projection (n·kOutputLanes)
  std::vector<double> one_minus_h;  ///< 1 − h per projection (n·kOutputLanes)
  std::vector<double> y;            ///< one block's outputs, padded (kOutputLanes)
  bool use_avx2 = has_avx2();       ///< as FieldScratch::use_avx2 (the same bits; tests compare)
  bool use_avx512 = has_avx512();   ///< as FieldScratch::use_avx512
  void resize(int n);
};

/// Whether the outputs' copies of one field (copies[o] is output o's) agree on every shared
/// member bit for bit (centre, metric and its factor, log_alpha, meta_trace, λ, x₀, trust, sum_w(0)
/// and n_data(0)), so that pack_lane_field() keeps everything. Precondition: the same input dimension.
bool lane_copies_agree(const std::vector<const ReceptiveField*>& copies);

/// The lane form of one field from its outputs' copies (copies[o] is output o's). Precondition:
/// lane_copies_agree(copies).
LaneField pack_lane_field(const std::vector<const ReceptiveField*>& copies);

/// Output o's copy of the field, as the per-output representation holds it (bit for bit what
/// pack_lane_field() was given, or what update_receptive_field() would have made of it).
ReceptiveField unpack_lane_field(const LaneField& field, int output);

/// add_projection() on output o's copy (R → R+1, the new projection's statistics as
/// add_projection() sets them; the arrays grow when R + 1 > max_reg). Precondition: R < n.
void add_lane_projection(const LwprParams& params, LaneField& field, int output);

/// update_receptive_field() of every output's copy with the sample (x, y) seen with activation
/// w > 0 (y: the n_out normalised outputs). Precondition: !params.update_D. Each copy ends with the
/// bits update_receptive_field() gives it.
void update_lane_field(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, const double* y,
                       double w, LaneField& field, LaneScratch& scratch);

/// update_lane_field() of two different fields with the same sample, their projections' scalar
/// chains in turn (as update_receptive_field_pair()); the same bits as one at a time.
void update_lane_field_pair(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, const double* y,
                            double w_a, LaneField& field_a, double w_b, LaneField& field_b, LaneScratch& scratch_a,
                            LaneScratch& scratch_b);

/// predict_receptive_field() of every output's copy at x: y[o] for the n_out outputs and, unless
/// `leverage` is null, leverage[o]; the same bits as predict_receptive_field() and
/// predict_receptive_field_value() on each copy.
void predict_lane_field(const LaneField& field, const Eigen::VectorXd& x, double* y, double* leverage,
                        LaneScratch& scratch);

/// calc_field_noise_variance() of output o's copy.
double calc_lane_noise_variance(const LaneField& field, int output);

/// The doubles LwprModel::calc_memory_bytes() counts for the field's n_out copies: the same as for
/// n_out ReceptiveFields (their members' sizes plus five scalars each).
std::size_t count_lane_field_doubles(const LaneField& field);

}  // namespace armfarm::lwpr
