#include "engine/control/step_stability.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

/// A PD period's maps of the linear plant ẋ = A x + G τ (x = (q, q̇), τ held): x' = Φ x + Γ τ.
struct PeriodMap {
  Eigen::MatrixXd phi;    ///< 2n × 2n
  Eigen::MatrixXd gamma;  ///< 2n × n
};

/// A = [[0, I], [0, −M⁻¹B]], G = [0; M⁻¹].
void make_plant_matrices(const Eigen::MatrixXd& mass_inverse, const Eigen::VectorXd& damping, Eigen::MatrixXd& a, Eigen::MatrixXd& g) {
  const Eigen::Index n = mass_inverse.rows();
  a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomRightCorner(n, n) = -mass_inverse * damping.asDiagonal();
  g = Eigen::MatrixXd::Zero(2 * n, n);
  g.bottomRows(n) = mass_inverse;
}

/// S classical RK4 steps of h_i each. For a linear system with τ constant one step is
/// x' = R(Z) x + h_i·Q(Z)·G τ, Z = h_i A, R = I + Z + Z²/2 + Z³/6 + Z⁴/24, Q = I + Z/2 + Z²/6 + Z³/24.
PeriodMap make_runge_kutta_map(const Eigen::MatrixXd& a, const Eigen::MatrixXd& g, double step, int steps) {
  const Eigen::Index size = a.rows();
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(size, size);
  const Eigen::MatrixXd z = step * a;
  const Eigen::MatrixXd z2 = z * z;
  const Eigen::MatrixXd z3 = z2 * z;
  const Eigen::MatrixXd r = identity + z + z2 / 2.0 + z3 / 6.0 + z3 * z / 24.0;
  const Eigen::MatrixXd q = step * (identity + z / 2.0 + z2 / 6.0 + z3 / 24.0) * g;
  PeriodMap map{identity, Eigen::MatrixXd::Zero(size, g.cols())};
  for (int s = 0; s < steps; ++s) {
    map.gamma = r * map.gamma + q;
    map.phi = r * map.phi;
  }
  return map;
}

/// The exact period map: exp(h·[[A, G], [0, 0]]) = [[Φ, Γ], [0, I]].
PeriodMap make_exact_map(const Eigen::MatrixXd& a, const Eigen::MatrixXd& g, double period) {
  const Eigen::Index size = a.rows(), inputs = g.cols();
  Eigen::MatrixXd augmented = Eigen::MatrixXd::Zero(size + inputs, size + inputs);
  augmented.topLeftCorner(size, size) = a * period;
  augmented.topRightCorner(size, inputs) = g * period;
  const Eigen::MatrixXd exponential = augmented.exp();
  return PeriodMap{exponential.topLeftCorner(size, size), exponential.topRightCorner(size, inputs)};
}

/// The index of the largest |v_j| + h·|v_{n+j}| (position and velocity parts of a mode, in rad).
int find_dominant_joint(const Eigen::VectorXcd& mode, Eigen::Index n, double period) {
  int best = 0;
  double largest = -1.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double weight = std::abs(mode[j]) + (mode.size() > n ? period * std::abs(mode[n + j]) : 0.0);
    if (weight > largest) {
      largest = weight;
      best = static_cast<int>(j);
    }
  }
  return best;
}

/// λ_max(M⁻¹B) and the joint its mode moves most.
void calc_passive_rate(const Eigen::MatrixXd& mass, const Eigen::VectorXd& damping, double& rate, int& joint) {
  const Eigen::MatrixXd b = damping.asDiagonal();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(b, mass);
  const Eigen::Index last = solver.eigenvalues().size() - 1;
  rate = std::max(0.0, solver.eigenvalues()[last]);
  joint = find_dominant_joint(solver.eigenvectors().col(last).cast<std::complex<double>>(), mass.rows(), 0.0);
}

void check_sizes(const LoopPlant& plant, const LoopGains* gains) {
  const Eigen::Index n = plant.mass.rows();
  if (n < 1 || plant.mass.cols() != n || plant.damping.size() != n ||
      (gains && (gains->kp.size() != n || gains->kd.size() != n))) {
    throw std::invalid_argument("step stability: the mass matrix, damping and gains must have one row per active joint");
  }
}

}  // namespace

bool LoopStability::loop_stable() const { return spectral_radius <= 1.0 + 1e-9; }
bool LoopStability::integrator_stable() const { return passive_step_ratio < kRk4RealBound; }

LoopStability calc_loop_stability(const LoopPlant& plant, const LoopGains* gains, const LoopSteps& steps) {
  check_sizes(plant, gains);
  if (!(steps.dt > 0.0) || steps.pd_substeps < 1 || steps.integrator_steps < 1) {
    throw std::invalid_argument("step stability: dt must be positive and the step counts at least 1");
  }
  const Eigen::Index n = plant.mass.rows();
  const Eigen::LLT<Eigen::MatrixXd> factor(plant.mass);
  if (factor.info() != Eigen::Success) throw std::invalid_argument("step stability: the mass matrix is not positive definite");
  const Eigen::MatrixXd mass_inverse = factor.solve(Eigen::MatrixXd::Identity(n, n));
  const double period = steps.dt / steps.pd_substeps;
  const double step = period / steps.integrator_steps;

  LoopStability result;
  double rate = 0.0;
  calc_passive_rate(plant.mass, plant.damping, rate, result.joint);
  if (steps.fixed_step) result.passive_step_ratio = rate * step;
  if (gains) {
    Eigen::MatrixXd a, g;
    make_plant_matrices(mass_inverse, plant.damping, a, g);
    const PeriodMap map = steps.fixed_step ? make_runge_kutta_map(a, g, step, steps.integrator_steps) : make_exact_map(a, g, period);
    Eigen::MatrixXd feedback(n, 2 * n);
    feedback << Eigen::MatrixXd(gains->kp.asDiagonal()), Eigen::MatrixXd(gains->kd.asDiagonal());
    const Eigen::MatrixXd closed = map.phi - map.gamma * feedback;
    const Eigen::MatrixXd kd = gains->kd.asDiagonal();
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(kd, plant.mass, Eigen::EigenvaluesOnly);
    result.modal_kd_ratio = std::max(0.0, modes.eigenvalues().maxCoeff()) * period;
    const Eigen::EigenSolver<Eigen::MatrixXd> solver(closed, true);
    Eigen::Index worst = 0;
    solver.eigenvalues().cwiseAbs().maxCoeff(&worst);
    result.spectral_radius = std::abs(solver.eigenvalues()[worst]);
    if (!std::isfinite(result.spectral_radius)) result.spectral_radius = std::numeric_limits<double>::infinity();
    // The loop's worst mode names the joint unless the integrator is the one that fails.
    if (result.integrator_stable()) result.joint = find_dominant_joint(solver.eigenvectors().col(worst), n, period);
  }
  const int j = result.joint;
  result.inertia = plant.mass(j, j);
  if (gains) {
    result.kd_ratio = gains->kd[j] * period / result.inertia;
    result.kp_ratio = gains->kp[j] * period * period / result.inertia;
  }
  result.damping_ratio = plant.damping[j] * (steps.fixed_step ? step : period) / result.inertia;
  return result;
}

StepChoice calc_stable_steps(const std::vector<LoopPlant>& plants, const std::vector<LoopGains>& controllers, double dt,
                             bool fixed_step, int fixed_pd, int fixed_integrator, double margin) {
  // The passive decay rate of each plant sets the fewest RK4 steps per tick it needs.
  double fastest = 0.0;
  for (const LoopPlant& plant : plants) {
    check_sizes(plant, nullptr);
    double rate = 0.0;
    int joint = 0;
    calc_passive_rate(plant.mass, plant.damping, rate, joint);
    fastest = std::max(fastest, rate);
  }
  const auto all_stable = [&](int pd, int integrator) {
    const LoopSteps steps{dt * margin, pd, integrator, fixed_step};
    for (const LoopPlant& plant : plants) {
      if (controllers.empty() && !calc_loop_stability(plant, nullptr, steps).stable()) return false;
      for (const LoopGains& gains : controllers) {
        if (!calc_loop_stability(plant, &gains, steps).stable()) return false;
      }
    }
    return true;
  };
  const int first_pd = fixed_pd > 0 ? fixed_pd : 1;
  const int last_pd = fixed_pd > 0 ? fixed_pd : kMaxPdSubsteps;
  for (int pd = first_pd; pd <= last_pd; ++pd) {
    int integrator = 1;
    if (fixed_integrator > 0) {
      integrator = fixed_integrator;
    } else if (fixed_step) {
      // λ·margin·dt/(P·S) < kRk4RealBound, with a hair of room for rounding.
      const double needed = fastest * margin * dt / pd / (kRk4RealBound * (1.0 - 1e-9));
      integrator = static_cast<int>(std::min<double>(kMaxIntegratorSteps, std::max(1.0, std::ceil(needed))));
    }
    // The loop also feels RK4's error at coarse steps: try twice the steps before a finer PD period.
    const int last_integrator = fixed_integrator > 0 || !fixed_step ? integrator : std::min(kMaxIntegratorSteps, 2 * integrator);
    if (all_stable(pd, integrator)) return StepChoice{pd, integrator, true};
    if (last_integrator != integrator && all_stable(pd, last_integrator)) return StepChoice{pd, last_integrator, true};
  }
  return StepChoice{last_pd, fixed_integrator > 0 ? fixed_integrator : (fixed_step ? kMaxIntegratorSteps : 1), false};
}

}  // namespace armfarm
