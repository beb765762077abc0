// SSGPR that fits its hyperparameters on its first samples, then learns them.
#include "engine/ssgpr/ssgpr_fitting_learner.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace armfarm::ssgpr {
namespace {

void require_sample_vector(const Eigen::VectorXd& v, int size, const char* name) {
  if (v.size() != size) {
    throw std::invalid_argument(std::string("SSGPR: ") + name + " has " + std::to_string(v.size()) + " elements, expected " +
                                std::to_string(size));
  }
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v(i))) throw std::invalid_argument(std::string("SSGPR: ") + name + "[" + std::to_string(i) + "] is not finite");
  }
}

}  // namespace

SsgprFittingLearner::SsgprFittingLearner(int n_in, int n_out, const SsgprParams& start, std::size_t fit_samples, SsgprFitConfig fit)
    : n_in_(n_in), n_out_(n_out), start_(start), fit_samples_(fit_samples), fit_(fit) {
  validate_ssgpr_params(start_, n_in, n_out);
  if (fit_samples_ < 2) throw std::invalid_argument("SSGPR parameter fit_samples must be >= 2");
  if (fit_.iterations < 1) throw std::invalid_argument("SSGPR parameter fit_iterations must be >= 1");
  fit_.max_samples = fit_samples_;
  kept_x_.reserve(fit_samples_);
  kept_y_.reserve(fit_samples_);
}

void SsgprFittingLearner::update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  if (model_) {
    model_->update(x, y);
    return;
  }
  require_sample_vector(x, n_in_, "x");
  require_sample_vector(y, n_out_, "y");
  kept_x_.push_back(x);
  kept_y_.push_back(y);
  if (kept_x_.size() < fit_samples_) return;

  const auto start = std::chrono::steady_clock::now();
  const Eigen::Index n = static_cast<Eigen::Index>(kept_x_.size());
  Eigen::MatrixXd X(n, n_in_), Y(n, n_out_);
  for (Eigen::Index i = 0; i < n; ++i) {
    X.row(i) = kept_x_[i].transpose();
    Y.row(i) = kept_y_[i].transpose();
  }
  SsgprParams fitted;
  try {
    fitted = calc_fitted_params(X, Y, start_, fit_, &report_);
  } catch (const std::exception& error) {
    kept_x_.pop_back();  // the learner stays as it was before this call
    kept_y_.pop_back();
    throw std::runtime_error("SSGPR hyperparameter fit on the first " + std::to_string(n) + " samples: " + error.what());
  }
  // The fit alone is one-off work; learning the kept samples is ordinary per-sample learning.
  fit_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  SsgprModel model(n_in_, n_out_, fitted);
  for (std::size_t i = 0; i < kept_x_.size(); ++i) model.update(kept_x_[i], kept_y_[i]);
  model_.emplace(std::move(model));
  kept_x_ = {};
  kept_y_ = {};
}

std::unique_ptr<PredictionWorkspace> SsgprFittingLearner::make_workspace() const {
  auto workspace = std::make_unique<SsgprWorkspace>();
  workspace->features.resize(2 * start_.features);
  workspace->solved.resize(2 * start_.features);
  return workspace;
}

Prediction SsgprFittingLearner::predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace) const {
  if (model_) return model_->predict(x, workspace);
  require_sample_vector(x, n_in_, "x");
  if (dynamic_cast<SsgprWorkspace*>(&workspace) == nullptr) {
    throw std::invalid_argument("SSGPR: predict() needs a workspace made by an SSGPR learner");
  }
  Prediction p;
  p.value = Eigen::VectorXd::Zero(n_out_);
  p.confidence = Eigen::VectorXd::Constant(n_out_, std::numeric_limits<double>::infinity());
  p.output_trusted.assign(n_out_, false);
  p.max_activation = 0.0;
  p.trustworthy = false;
  return p;
}

std::uint64_t SsgprFittingLearner::n_updates() const {
  return model_ ? model_->n_updates() : static_cast<std::uint64_t>(kept_x_.size());
}

std::size_t SsgprFittingLearner::calc_memory_bytes() const {
  if (model_) return model_->calc_memory_bytes();
  return sizeof(double) * kept_x_.size() * static_cast<std::size_t>(n_in_ + n_out_);
}

}  // namespace armfarm::ssgpr
