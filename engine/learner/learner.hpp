#pragma once
// The interface the controller and the runner use to learn a mapping x -> y online or in
// batch, without depending on a particular learner (LWPR is engine/lwpr/).
#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <variant>
#include <vector>

namespace armfarm {

namespace lwpr {
class LwprModel;
}
namespace ssgpr {
class SsgprModel;
class SsgprFittingLearner;
}  // namespace ssgpr

/// The closed set of concrete learners (the one list of them): what Learner::concrete() returns
/// and visit_learner() dispatches on. A new learner is a new alternative here, and every dispatch
/// that lacks its case stops compiling.
using ConcreteLearner = std::variant<const lwpr::LwprModel*, const ssgpr::SsgprModel*, const ssgpr::SsgprFittingLearner*>;

/// One prediction, y (n_out × 1), with a per-output confidence half-width (same units as y),
/// the largest kernel activation that contributed, and per output whether a local model was
/// trustworthy enough to predict it at x. Where `output_trusted[o]` is false, `value[o]` is not
/// a prediction (it is zero, its confidence +inf) and callers must not use it as one; the other
/// outputs are unaffected. `trustworthy` is true when every output is trusted.
struct Prediction {
  Eigen::VectorXd value;
  Eigen::VectorXd confidence;
  std::vector<bool> output_trusted;  ///< n_out
  double max_activation = 0.0;
  bool trustworthy = false;
};

/// Caller-owned scratch space for predictions, so that predict() can be const and several
/// threads can predict from one learner, each with its own workspace.
class PredictionWorkspace {
 public:
  virtual ~PredictionWorkspace() = default;
};

class Learner {
 public:
  virtual ~Learner() = default;

  virtual int input_dim() const = 0;
  virtual int output_dim() const = 0;

  /// Learns one sample. Throws std::invalid_argument (model unchanged) if x or y has the wrong
  /// size or holds NaN or Inf.
  virtual void update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) = 0;

  virtual std::unique_ptr<PredictionWorkspace> make_workspace() const = 0;
  /// Predicts y at x; const and thread-safe given one workspace per thread.
  virtual Prediction predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace) const = 0;
  /// predict() into `out`, overwriting every member. A learner that overrides it reuses out's
  /// vectors, so a caller that keeps one Prediction across calls allocates nothing per call.
  virtual void predict_into(const Eigen::VectorXd& x, PredictionWorkspace& workspace, Prediction& out) const {
    out = predict(x, workspace);
  }
  /// predict_into() without the confidence bounds, for callers that read only the values, the
  /// trust flags and max_activation: `out.confidence` is left with 0 elements, every other member
  /// is what predict_into() writes. A learner that overrides it skips the bounds' work (LWPR: the
  /// fields' leverages and noise variances); the default computes them and drops them.
  virtual void predict_values_into(const Eigen::VectorXd& x, PredictionWorkspace& workspace, Prediction& out) const {
    predict_into(x, workspace, out);
    out.confidence.resize(0);
  }

  /// Number of local models (LWPR: receptive fields summed over outputs).
  virtual std::size_t size() const = 0;

  /// Samples learnt so far (successful update() calls); a frozen learner's count never moves.
  virtual std::uint64_t n_updates() const = 0;

  /// Bytes of the numbers the learnt model stores (8 per double, 1 per flag; its scratch but not
  /// the callers' workspaces, nor object or allocator overheads, so that the figure is the same
  /// on every machine and standard library): the learner_memory_bytes metric.
  virtual std::size_t calc_memory_bytes() const = 0;

  /// Wall-clock seconds spent inside update() on one-off work that is not per-sample learning
  /// (SSGPR's hyperparameter fit on its first batch); 0 for a learner without any. The job's
  /// µs-per-update metric excludes it and reports it apart (learner_fit_seconds).
  virtual double fit_seconds() const { return 0.0; }

  /// This learner as its concrete type (never null); use visit_learner() rather than casts.
  virtual ConcreteLearner concrete() const = 0;
};

/// The one learner-kind dispatch: calls the case of `cases` that takes the learner's concrete
/// type (const lwpr::LwprModel&, const ssgpr::SsgprModel& or const ssgpr::SsgprFittingLearner&)
/// and returns its result. A missing case is a compile error.
template <typename... Cases>
decltype(auto) visit_learner(const Learner& learner, Cases&&... cases) {
  struct Overloaded : std::decay_t<Cases>... {
    using std::decay_t<Cases>::operator()...;
  };
  Overloaded visitor{std::forward<Cases>(cases)...};
  return std::visit([&](const auto* concrete) -> decltype(auto) { return visitor(*concrete); }, learner.concrete());
}

}  // namespace armfarm
