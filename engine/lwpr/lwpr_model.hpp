#pragma once
// An LWPR model (Vijayakumar, D'Souza & Schaal 2005): one independent set of receptive fields
// per output, each field a locally weighted PLS regression. Inputs and outputs are in the
// caller's units; the model normalises them by LwprParams::norm_in / norm_out internally.
#include "engine/learner/learner.hpp"
#include "engine/lwpr/lane_fields.hpp"
#include "engine/lwpr/lwpr_params.hpp"
#include "engine/lwpr/receptive_field.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace armfarm::lwpr {

/// A field found active by the activation scan: its index in the output's list and its activation.
struct ActiveField {
  std::size_t index;
  double w;
};

/// Scratch space of LwprModel::predict (one per thread).
class LwprWorkspace final : public PredictionWorkspace {
 public:
  Eigen::VectorXd x_normalised;
  std::vector<double> x_padded;  ///< x_normalised padded with zeros to the scan stride
  FieldScratch scratch;
  std::vector<ActiveField> active;  ///< the shared scan's active trustworthy fields
  std::vector<double> scan_diff;    ///< the full-metric scan's x − c of a group (n_in × 4)
  LaneScratch lane_scratch;         ///< the lane form's prediction scratch
  std::vector<double> lane_values;  ///< the lane form's predictions, active field k's output o at [k·n_out + o]
  std::vector<double> lane_leverages;  ///< their leverages, likewise
};

/// How a model stores its fields. kAuto: without update_D, for more than 3 inputs and at least 2
/// outputs, each field once with its outputs' regressions in vector lanes (lane_fields.hpp), else
/// one list per output; kPerOutput: one list per output always. Both give the same bits (tests
/// compare them).
enum class FieldLayout { kAuto, kPerOutput };

/// Per-output detail of a prediction (all sizes n_out), in the caller's units.
struct LwprPredictionDetail {
  Eigen::VectorXd max_activation;  ///< largest activation among the output's trustworthy fields
  std::vector<bool> trustworthy;   ///< whether any trustworthy field was active for the output
};

class LwprModel final : public Learner {
 public:
  /// An empty model (no fields) learning n_in → n_out. Throws std::invalid_argument if the
  /// parameters are invalid for these sizes (see validate_lwpr_params()).
  LwprModel(int n_in, int n_out, const LwprParams& params, FieldLayout layout = FieldLayout::kAuto);

  /// A model restored from saved state: `fields` has one list per output, `n_updates` the samples
  /// learnt. Throws std::invalid_argument if the sizes are inconsistent.
  LwprModel(int n_in, int n_out, const LwprParams& params, std::vector<std::vector<ReceptiveField>> fields,
            std::uint64_t n_updates, FieldLayout layout = FieldLayout::kAuto);

  int input_dim() const override { return n_in_; }
  int output_dim() const override { return n_out_; }

  /// Learns (x, y) (n_in, n_out): updates every field activated more than `cutoff`, creates a
  /// field at x for an output where no field is activated more than w_gen (unless at max_fields),
  /// and prunes one of two fields activated more than w_prune. Throws std::invalid_argument with
  /// the model unchanged if a size is wrong or x or y holds NaN or Inf.
  void update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) override;

  std::unique_ptr<PredictionWorkspace> make_workspace() const override;

  /// Blended (or winner-take-all) prediction at x with a one-standard-deviation confidence per
  /// output. An output with no trustworthy active field has output_trusted false, value 0 and
  /// confidence +∞; `trustworthy` is false if any output is untrusted. max_activation is the smallest over outputs of each
  /// output's largest activation. Throws std::invalid_argument for a wrong size, a non-finite x,
  /// or a workspace not made by this class.
  Prediction predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace) const override;

  /// predict() plus the per-output activations and trust flags.
  Prediction predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace, LwprPredictionDetail& detail) const;

  /// predict() into `out`: no allocation once out's vectors have n_out elements.
  void predict_into(const Eigen::VectorXd& x, PredictionWorkspace& workspace, Prediction& out) const override;

  /// predict_into() without confidence bounds (out.confidence empty): the same values, trust flags
  /// and max_activation, bit for bit, without the fields' leverages and noise variances.
  void predict_values_into(const Eigen::VectorXd& x, PredictionWorkspace& workspace, Prediction& out) const override;

  /// Receptive fields summed over outputs.
  std::size_t size() const override;

  const LwprParams& params() const { return params_; }
  /// Output `output`'s fields (a copy: in the lane form they are unpacked).
  std::vector<ReceptiveField> fields(int output) const;
  /// The number of output `output`'s fields.
  std::size_t field_count(int output) const;
  /// Whether the fields are stored in the lane form (FieldLayout).
  bool lane_layout() const { return lane_layout_; }
  std::uint64_t n_updates() const override { return n_updates_; }
  /// Bytes of the fields' numbers (every statistic and cached derivative) and the activation
  /// scan's data (Learner::calc_memory_bytes).
  std::size_t calc_memory_bytes() const override;
  ConcreteLearner concrete() const override { return this; }
  /// Mean number of PLS projections per receptive field (0 without fields).
  double calc_mean_projections() const;

 private:
  // Updates output `output` with y (normalised) given the fields active at x (every field with
  // w > 0, in field order), creating and pruning as update() says.
  void update_output(int output, double y, const std::vector<ActiveField>& active);
  // The active fields' updates of update_output(), kFieldGroup at a time; the most active field and the
  // first two above w_prune (−1 where none).
  struct ActiveSummary {
    double w_max = 0.0;
    int i_max = -1;
    int prune_a = -1;
    int prune_b = -1;
    // Takes one active field into account (in the scan's order).
    void note(const ActiveField& a, double w_prune);
  };
  ActiveSummary update_active_fields(int output, double y, const std::vector<ActiveField>& active);
  // update_output() of every output at once in the lane form (y: the normalised outputs).
  void update_lane_fields(const double* y, const std::vector<ActiveField>& active);
  // x (n_in elements, checked) divided by norm_in into `normalised` and the first n_in of
  // `padded`; throws require_vector()'s error for the first non-finite element.
  void normalise_input(const Eigen::VectorXd& x, double* normalised, double* padded) const;
  // Every predict(): writes `prediction` (its confidence only `with_bounds`, else left empty);
  // `detail` (may be null: then nothing of it is allocated) receives the per-output activations
  // and trust flags.
  void predict_with(const Eigen::VectorXd& x, PredictionWorkspace& workspace, LwprPredictionDetail* detail,
                    bool with_bounds, Prediction& prediction) const;
  // The fields of `output`'s scan active at x_padded (w > 0), in field order; only trustworthy
  // ones when `trusted_only`. `avx2` picks the AVX2 copy (FieldScratch::use_avx2); `diff` is
  // scratch of n_in × 4 doubles.
  void scan_active(int output, const double* x_padded, bool trusted_only, bool avx2, double* diff,
                   std::vector<ActiveField>& active) const;
  // scan_active's loop, inlined into the portable copy and into the AVX2 one: the same operations
  // and summation order, no FMA, so the same bits. Every metric is scanned four fields at a time,
  // one per vector lane (scan_groups in the .cpp).
  __attribute__((always_inline)) inline void scan_active_loop(int output, const double* x_padded, bool trusted_only,
                                                              double* diff, std::vector<ActiveField>& active) const;
  __attribute__((target("avx2"))) void scan_active_avx2(int output, const double* x_padded, bool trusted_only,
                                                        double* diff, std::vector<ActiveField>& active) const;
  // Whether every output's scan data (centres, metrics, trust flags) are the same.
  bool calc_scans_identical() const;
  // Appends a field (a ReceptiveField or a LaneField) to `output`'s scan data (as its last field).
  template <class Field>
  void append_to_scan(int output, const Field& rf);
  // Writes field i's metric into `output`'s scan data, in the group layout: a diagonal's
  // elements, or a full metric's factor's upper triangle row by row.
  template <class Field>
  __attribute__((always_inline)) inline void write_scan_metric(int output, std::size_t i, const Field& rf);
  // Removes field `victim` from `output`'s scan data (later fields move down one place).
  void erase_from_scan(int output, std::size_t victim);
  // Where field i's element 0 is in the centres' group layout (element k at + k·kScanGroup).
  std::size_t calc_group_offset(std::size_t i) const;
  // The same in the metrics' group layout (metric_stride_ elements per field).
  std::size_t calc_metric_offset(std::size_t i) const;

  // The activation scan's data of one output, in the order of fields_[o] and kept in step with it
  // on every create, update and prune. Centres and metrics in the group layout: groups of
  // kScanGroup (4) fields, element k of the group's field l at [k·kScanGroup + l], zero-padded
  // (lanes past the last field, and for centres and diagonal metrics elements past n_in), so that
  // one vector operation serves four fields. A group holds stride_ × kScanGroup centre doubles and
  // metric_stride_ × kScanGroup metric doubles: a diagonal metric (stride_ elements), or a full
  // metric's factor M, its upper triangle row by row (n(n+1)/2 elements). The trust flags, one per
  // field and one byte per group (bit l: field l of the group is trustworthy), so that
  // prediction's scan takes a group's lanes with one load. Contiguous, so the scan over hundreds
  // of fields streams through memory instead of chasing each field's heap blocks.
  struct ScanData {
    std::vector<double> centres;
    std::vector<double> metrics;
    std::vector<unsigned char> trusted;
    std::vector<unsigned char> trusted_lanes;
  };
  // Sets field i's trust flag in both of `scan`'s forms.
  static void write_scan_trust(ScanData& scan, std::size_t i, bool trusted);

  int n_in_;
  int n_out_;
  LwprParams params_;
  Eigen::MatrixXd init_metric_;  // n_in×n_in
  Eigen::VectorXd norm_in_;
  Eigen::VectorXd norm_out_;
  double trust_n_data_;
  std::vector<std::vector<ReceptiveField>> fields_;
  std::vector<ScanData> scan_;
  int stride_;       // n_in rounded up to a multiple of the scan block
  bool diagonal_scan_;  // metrics scanned as diagonals: diag_only, or n_in = 1
  int metric_stride_;  // metric elements per field in ScanData::metrics: stride_ (diagonal) or n_in(n_in+1)/2
  double q_limit_;   // calc_q_limit(kernel, cutoff)
  // Every output holds the same fields' centres, metrics and trust flags, so one scan serves all
  // outputs. Without update_D a field's metric never changes, and creation (w_gen, the nearest
  // trustworthy field), trust (n_data counts samples, whatever y) and pruning (trace D) do not
  // depend on the output, so the outputs' field sets stay identical; set when the model is built
  // (checked on restored fields) and kept by construction.
  bool shared_scan_ = false;
  // The lane form (FieldLayout): lane_fields_ holds the fields, fields_ is empty, and scan_[0] is
  // the one scan (shared_scan_ holds).
  bool lane_layout_ = false;
  std::vector<LaneField> lane_fields_;
  LaneScratch lane_scratch_;
  LaneScratch lane_scratch_pair_;
  std::vector<double> y_normalised_;  // update()'s y / norm_out (n_out)
  std::uint64_t n_updates_ = 0;
  // Update scratch (update() is not const; predict() uses the caller's workspace instead).
  Eigen::VectorXd x_normalised_;
  std::vector<double> x_padded_;
  FieldScratch scratch_;
  FieldScratch group_scratch_[kFieldGroup - 1];  // the other fields' of update_receptive_fields
  std::vector<ActiveField> active_;
  std::vector<double> scan_diff_;  // scan_active's diff (n_in × 4)
};

}  // namespace armfarm::lwpr
