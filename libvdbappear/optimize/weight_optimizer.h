#pragma once
// Stochastic gradient descent on the lobe-weight factors (§6.3-6.4 of the downsampling paper):
// starting from w = 1 (and s = 1), each iteration t renders every training image of the reduced
// medium with the current factors, twice with fresh seeds and with gradient images from the same
// paths (Appendix A), estimates E (Eq. 14) and dE/dtheta (Eq. 16, chain rule of
// optimize/weight_factors.h), and steps theta -= A / (t + b) dE/dtheta (Eq. 17-18, A from the mean
// of the iterations' Gauss-Newton matrices by optimize/step_sizes.h), shortened when a factor would
// change by more than kMaxRelativeChange or leave the feasible set (every effective albedo at most
// 1: then shortened by bisection to its edge), then applies constrainFactors (optimize/lobe_medium.h).
//
// Convergence test: after at least min_iterations, stop when in each of the last three iterations
// no factor changed by more than `tolerance` (relative); else stop after max_iterations.
//
// Iteration t, image i, half h draws its seed from (seed, t, i, h), and renders do not depend on
// the thread count, so a run is the same for any -j, and a run resumed from a checkpoint is the
// same as one never interrupted. Light header.

#include "libvdbappear/optimize/lobe_medium.h"
#include "libvdbappear/optimize/step_sizes.h"
#include "libvdbappear/optimize/training_error.h"
#include "libvdbappear/optimize/weight_factors.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace vdbappear {

// The trust region of one iteration: no factor changes by more than this (relative); a longer step
// is shortened as a whole. Guards against steps along directions that one iteration's noisy
// Jacobian mistakes for flat.
inline constexpr double kMaxRelativeChange = 0.25;

struct OptimizerSettings {
  ColourMode mode = ColourMode::kGrey;
  int spp = 8;              // samples per pixel of each training image per iteration (two halves)
  int max_iterations = 30;
  int min_iterations = 5;
  double tolerance = 0.005;
  StepRule step_rule = StepRule::kNewton;  // optimize/step_sizes.h
  double step_b = 1;        // b of Eq. 18
  double step_scale = 1;    // multiplies the tuned a (1: the rule of step_sizes.h)
  std::uint64_t seed = 0;
  PathSettings path;
  nlohmann::json toJson() const;
  // The settings that change the iterates (not when to stop): what a checkpoint must share to be
  // resumed.
  nlohmann::json iterateJson() const;
};

struct IterationRecord {
  int t = 0;
  double E = 0;                    // Eq. 14 at the factors the iteration started from
  std::vector<double> theta;       // those factors (WeightFactors::parameters)
  std::vector<double> gradient;    // dE/dtheta there
  std::vector<double> step;        // the diagonal of delta_t (Eq. 18)
  std::vector<double> per_image;   // E of each training image
  std::vector<std::vector<Rgb>> relative_errors;  // TrainingError::relative_errors (not checkpointed)
  double relative_change = 0;      // largest |theta_new - theta| / theta of this iteration's update
  bool limited = false;            // the effective-albedo limit shortened or changed the update
  bool shortened = false;          // the trust region shortened the step
  double seconds = 0;
  nlohmann::json toJson(const std::vector<std::string>& names) const;  // a line of the JSON-lines log
};

class WeightOptimizer {
 public:
  WeightOptimizer(TrainingScenes& scenes, std::vector<TrainingImage> images, LobeMediumLayout layout,
                  const OptimizerSettings& settings);

  // One SGD iteration; returns its record.
  const IterationRecord& iterate();
  bool converged() const;
  bool done() const { return converged() || iteration() >= settings_.max_iterations; }
  int iteration() const { return int(history_.size()); }

  const WeightFactors& factors() const { return factors_; }
  const StepSizes& steps() const { return steps_; }
  const std::vector<IterationRecord>& history() const { return history_; }
  const std::vector<TrainingImage>& images() const { return images_; }
  const OptimizerSettings& settings() const { return settings_; }

  // E (Eq. 14) at `factors` from fresh renders without gradients, seeded by (seed, key).
  TrainingError evaluate(const WeightFactors& factors, std::int64_t key);

  // The state after the last iteration, with `inputs` (what the run depends on: content hashes,
  // settings) so that resume() can refuse a checkpoint of another run.
  nlohmann::json checkpoint(const nlohmann::json& inputs) const;
  // Throws std::invalid_argument when the checkpoint is not one, is of another format or version,
  // or was made with other inputs.
  void resume(const nlohmann::json& checkpoint, const nlohmann::json& inputs);

 private:
  TrainingError renderAll(const WeightFactors& factors, std::int64_t key, bool gradients);

  TrainingScenes& scenes_;
  std::vector<TrainingImage> images_;
  LobeMediumLayout layout_;
  OptimizerSettings settings_;
  WeightFactors factors_;
  StepSizes steps_;
  std::vector<IterationRecord> history_;
  GaussNewton gauss_newton_sum_;  // sum over the iterations
};

}  // namespace vdbappear
