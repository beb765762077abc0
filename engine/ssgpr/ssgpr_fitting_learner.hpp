#pragma once
// An SSGPR learner that fits its own hyperparameters on the first samples it is given: it keeps
// the first `fit_samples` samples (predicting nothing meanwhile: every output untrusted), fits
// lengthscales, σ_f², σ_n² (and output_scale) to them by the GP marginal likelihood
// (ssgpr_fit.hpp), builds the SsgprModel from the fitted parameters and learns the kept samples
// in their order. From then on it is that model. So a job's learner needs no data before its
// first update: online, the fit batch is the first ticks of the learning pass; batch, the first
// shuffled training samples. The fit is one-off work inside one update() call, timed apart
// (fit_seconds(), the fit alone: learning the kept samples afterwards is per-sample work).
#include "engine/learner/learner.hpp"
#include "engine/ssgpr/ssgpr_fit.hpp"
#include "engine/ssgpr/ssgpr_model.hpp"

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

namespace armfarm::ssgpr {

class SsgprFittingLearner final : public Learner {
 public:
  /// `start`: the parameters the fit starts from (and keeps: features, forgetting, seed, trust,
  /// resolve_interval); `fit_samples` ≥ 2; fit.max_samples is replaced by fit_samples. Throws
  /// std::invalid_argument for invalid parameters.
  SsgprFittingLearner(int n_in, int n_out, const SsgprParams& start, std::size_t fit_samples, SsgprFitConfig fit);

  int input_dim() const override { return n_in_; }
  int output_dim() const override { return n_out_; }

  /// Keeps (x, y) until fit_samples are kept, then fits and learns them; afterwards
  /// SsgprModel::update. Throws std::invalid_argument (nothing kept or learnt) for a wrong size
  /// or NaN/Inf; std::runtime_error "SSGPR hyperparameter fit on the first N samples: ..." if the
  /// fit fails (the samples stay kept and the learner unfitted).
  void update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) override;

  /// An SsgprWorkspace, usable before and after the fit.
  std::unique_ptr<PredictionWorkspace> make_workspace() const override;
  /// Before the fit: value 0, confidence +∞, every output untrusted; after it: the model's.
  Prediction predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace) const override;

  /// D.
  std::size_t size() const override { return static_cast<std::size_t>(start_.features); }
  /// Samples kept (before the fit) or learnt.
  std::uint64_t n_updates() const override;
  /// The kept samples' bytes, or the model's.
  std::size_t calc_memory_bytes() const override;
  double fit_seconds() const override { return fit_seconds_; }
  ConcreteLearner concrete() const override { return this; }

  bool fitted() const { return model_.has_value(); }
  /// Samples the fit waits for.
  std::size_t fit_samples() const { return fit_samples_; }
  /// The fitted model; precondition: fitted().
  const SsgprModel& model() const { return *model_; }
  const SsgprFitReport& fit_report() const { return report_; }

 private:
  int n_in_;
  int n_out_;
  SsgprParams start_;
  std::size_t fit_samples_;
  SsgprFitConfig fit_;
  std::vector<Eigen::VectorXd> kept_x_, kept_y_;
  std::optional<SsgprModel> model_;
  SsgprFitReport report_;
  double fit_seconds_ = 0.0;
};

}  // namespace armfarm::ssgpr
