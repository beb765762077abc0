// SSGPR model: random Fourier features, rank-one Cholesky updates, posterior mean and variance.
#include "engine/ssgpr/ssgpr_model.hpp"

#include "engine/random/random_stream.hpp"
#include "engine/ssgpr/cholesky_update.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace armfarm::ssgpr {
namespace {

void require_vector(const Eigen::VectorXd& v, int size, const char* name) {
  if (v.size() != size) {
    throw std::invalid_argument(std::string("SSGPR: ") + name + " has " + std::to_string(v.size()) +
                                " elements, expected " + std::to_string(size));
  }
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v(i))) {
      throw std::invalid_argument(std::string("SSGPR: ") + name + "[" + std::to_string(i) + "] is not finite");
    }
  }
}

void require_shape(const Eigen::MatrixXd& m, Eigen::Index rows, Eigen::Index cols, const char* name) {
  if (m.rows() != rows || m.cols() != cols) {
    throw std::invalid_argument(std::string("SSGPR: ") + name + " is " + std::to_string(m.rows()) + "x" +
                                std::to_string(m.cols()) + ", expected " + std::to_string(rows) + "x" +
                                std::to_string(cols));
  }
  if (!m.allFinite()) throw std::invalid_argument(std::string("SSGPR: ") + name + " holds NaN or Inf");
}

}  // namespace

SsgprModel::SsgprModel(int n_in, int n_out, const SsgprParams& params)
    : n_in_(n_in), n_out_(n_out), params_(params) {
  validate_ssgpr_params(params_, n_in, n_out);
  output_scale_ = calc_expanded_vector(params_.output_scale, n_out);
  const int D = params_.features;
  const int F = 2 * D;
  feature_scale_ = std::sqrt(params_.signal_variance / D);
  const Eigen::VectorXd lengthscales = calc_expanded_vector(params_.lengthscales, n_in);
  RandomStream stream(params_.seed, "ssgpr.features");
  state_.frequencies.resize(D, n_in);
  for (int i = 0; i < D; ++i) {
    for (int d = 0; d < n_in; ++d) state_.frequencies(i, d) = stream.normal() / lengthscales(d);
  }
  state_.factor = Eigen::MatrixXd::Identity(F, F) * std::sqrt(params_.noise_variance);
  state_.rhs = Eigen::MatrixXd::Zero(F, n_out);
  state_.weights = Eigen::MatrixXd::Zero(F, n_out);
  phi_.resize(F);
  rotated_.resize(F);
  gain_.resize(F);
  y_scaled_.resize(n_out);
  error_.resize(n_out);
}

SsgprModel::SsgprModel(int n_in, int n_out, const SsgprParams& params, SsgprState state)
    : SsgprModel(n_in, n_out, params) {
  const Eigen::Index D = params_.features, F = 2 * D;
  require_shape(state.frequencies, D, n_in, "frequencies");
  require_shape(state.factor, F, F, "Cholesky factor");
  require_shape(state.rhs, F, n_out, "right-hand side");
  require_shape(state.weights, F, n_out, "weights");
  for (Eigen::Index k = 0; k < F; ++k) {
    if (!(state.factor(k, k) > 0.0)) throw std::invalid_argument("SSGPR: Cholesky factor has a non-positive diagonal");
  }
  state.factor.triangularView<Eigen::StrictlyUpper>().setZero();
  state_ = std::move(state);
}

void SsgprModel::calc_features(const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> features) const {
  const Eigen::Index D = params_.features;
  for (Eigen::Index i = 0; i < D; ++i) {
    const double angle = state_.frequencies.row(i).dot(x);
    features(i) = feature_scale_ * std::cos(angle);
    features(D + i) = feature_scale_ * std::sin(angle);
  }
}

void SsgprModel::update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  require_vector(x, n_in_, "x");
  require_vector(y, n_out_, "y");
  calc_features(x, phi_);
  if (!phi_.allFinite()) throw std::invalid_argument("SSGPR: the features of x are not finite (x too large)");
  y_scaled_ = y.cwiseQuotient(output_scale_);
  if (!y_scaled_.allFinite()) throw std::invalid_argument("SSGPR: y / output_scale is not finite");
  // From here on nothing throws: the model changes only after every check passed.
  const double lambda = params_.forgetting;
  if (lambda < 1.0) {
    state_.factor.triangularView<Eigen::Lower>() *= std::sqrt(lambda);
    state_.rhs *= lambda;
  }
  rotated_ = phi_;
  update_cholesky_rank_one(state_.factor, rotated_);
  state_.rhs.noalias() += phi_ * y_scaled_.transpose();
  ++state_.n_updates;
  if (params_.resolve_interval > 0 && state_.n_updates % params_.resolve_interval == 0) {
    resolve_weights();
    return;
  }
  // W_new = A_new⁻¹(λB + φyᵀ) = W + A_new⁻¹φ (y − Wᵀφ)ᵀ, since A_new W = λB + φφᵀW.
  gain_ = phi_;
  state_.factor.triangularView<Eigen::Lower>().solveInPlace(gain_);
  state_.factor.triangularView<Eigen::Lower>().transpose().solveInPlace(gain_);
  error_.noalias() = y_scaled_ - state_.weights.transpose() * phi_;
  state_.weights.noalias() += gain_ * error_.transpose();
}

void SsgprModel::resolve_weights() {
  state_.weights = state_.rhs;
  state_.factor.triangularView<Eigen::Lower>().solveInPlace(state_.weights);
  state_.factor.triangularView<Eigen::Lower>().transpose().solveInPlace(state_.weights);
}

std::unique_ptr<PredictionWorkspace> SsgprModel::make_workspace() const {
  auto workspace = std::make_unique<SsgprWorkspace>();
  workspace->features.resize(2 * params_.features);
  workspace->solved.resize(2 * params_.features);
  return workspace;
}

Prediction SsgprModel::predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace) const {
  SsgprPredictionDetail detail;
  return predict(x, workspace, detail);
}

Prediction SsgprModel::predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace,
                               SsgprPredictionDetail& detail) const {
  require_vector(x, n_in_, "x");
  auto* ws = dynamic_cast<SsgprWorkspace*>(&workspace);
  if (ws == nullptr) throw std::invalid_argument("SSGPR: predict() needs a workspace made by SsgprModel");
  ws->features.resize(2 * params_.features);
  calc_features(x, ws->features);
  if (!ws->features.allFinite()) throw std::invalid_argument("SSGPR: the features of x are not finite (x too large)");
  ws->solved = ws->features;
  state_.factor.triangularView<Eigen::Lower>().solveInPlace(ws->solved);
  const double quad = ws->solved.squaredNorm();  // φᵀA⁻¹φ
  const double latent = params_.noise_variance * quad;
  const Eigen::VectorXd scale2 = output_scale_.cwiseAbs2();
  detail.mean = (state_.weights.transpose() * ws->features).cwiseProduct(output_scale_);
  detail.latent_variance = latent * scale2;
  detail.predictive_variance = (params_.noise_variance + latent) * scale2;
  detail.variance_fraction = latent / params_.signal_variance;

  const bool trusted = state_.n_updates >= params_.trust_min_samples &&
                       (params_.trust_variance_fraction >= 1.0 ||
                        detail.variance_fraction <= params_.trust_variance_fraction);
  Prediction p;
  p.output_trusted.assign(n_out_, trusted);
  p.trustworthy = trusted;
  p.max_activation = std::min(1.0, std::max(0.0, 1.0 - detail.variance_fraction));
  if (trusted) {
    p.value = detail.mean;
    p.confidence = detail.predictive_variance.cwiseSqrt();
  } else {
    p.value = Eigen::VectorXd::Zero(n_out_);
    p.confidence = Eigen::VectorXd::Constant(n_out_, std::numeric_limits<double>::infinity());
  }
  return p;
}

std::size_t SsgprModel::calc_memory_bytes() const {
  const std::size_t doubles = static_cast<std::size_t>(state_.frequencies.size() + state_.factor.size() +
                                                       state_.rhs.size() + state_.weights.size() + phi_.size() +
                                                       rotated_.size() + gain_.size() + 2 * n_out_ + n_out_);
  return sizeof(double) * doubles;
}

}  // namespace armfarm::ssgpr
