#include "libvdbappear/optimize/weight_optimizer.h"

#include "libvdbappear/util/hash_random.h"
#include "libvdbappear/util/json_int.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace vdbappear {

nlohmann::json OptimizerSettings::toJson() const {
  return {{"mode", colourModeName(mode)}, {"spp", spp},           {"max_iterations", max_iterations},
          {"min_iterations", min_iterations}, {"tolerance", tolerance}, {"step_rule", stepRuleName(step_rule)}, {"step_b", step_b},
          {"step_scale", step_scale},         {"seed", seed},           {"max_depth", path.max_depth},
          {"roulette_depth", path.roulette_depth}};
}

nlohmann::json OptimizerSettings::iterateJson() const {
  nlohmann::json j = toJson();
  for (const char* stopping : {"max_iterations", "min_iterations", "tolerance"}) j.erase(stopping);
  return j;
}

nlohmann::json IterationRecord::toJson(const std::vector<std::string>& names) const {
  nlohmann::json factors = nlohmann::json::object(), gradients = nlohmann::json::object(), steps = nlohmann::json::object();
  for (std::size_t p = 0; p < theta.size() && p < names.size(); ++p) {
    factors[names[p]] = theta[p];
    if (p < gradient.size()) gradients[names[p]] = gradient[p];
    if (p < step.size()) steps[names[p]] = step[p];
  }
  return {{"t", t},         {"E", E},           {"factors", factors},          {"gradient", gradients},
          {"step", steps},   {"limited", limited}, {"shortened", shortened}, {"relative_change", relative_change}, {"seconds", seconds},
          {"E_per_image", per_image}};
}

WeightOptimizer::WeightOptimizer(TrainingScenes& scenes, std::vector<TrainingImage> images, LobeMediumLayout layout,
                                 const OptimizerSettings& settings)
    : scenes_(scenes), images_(std::move(images)), layout_(std::move(layout)), settings_(settings),
      factors_(layout_.clusters, layout_.lobes, settings.mode) {
  if (images_.size() != scenes_.size()) throw std::invalid_argument("WeightOptimizer: one training image per scene");
  if (settings_.spp < 2) throw std::invalid_argument("WeightOptimizer: spp must be >= 2 (two halves)");
  constrainFactors(layout_, factors_);  // w = 1 is feasible: the naive weights sum to the albedo
}

TrainingError WeightOptimizer::renderAll(const WeightFactors& factors, std::int64_t key, bool gradients) {
  const auto scales = std::make_shared<const LobeWeightScales>(factors.scales());
  TrainingError error;
  for (std::size_t i = 0; i < images_.size(); ++i) {
    RenderSettings s = trainingRenderSettings(images_[i].config.view, settings_.spp / 2,
                                              hashKeys(settings_.seed, {key, std::int64_t(i), 0}), settings_.path);
    s.weight_gradients = gradients;
    const RenderResult a = scenes_.render(i, s, scales);
    s.seed = hashKeys(settings_.seed, {key, std::int64_t(i), 1});
    const RenderResult b = scenes_.render(i, s, scales);
    addTrainingImage(images_[i], a, b, &error);
  }
  return error;
}

TrainingError WeightOptimizer::evaluate(const WeightFactors& factors, std::int64_t key) {
  return renderAll(factors, -1 - key, false);  // negative keys: never an iteration's seeds
}

const IterationRecord& WeightOptimizer::iterate() {
  const Stopwatch clock;
  IterationRecord record;
  record.t = iteration() + 1;
  const TrainingError error = renderAll(factors_, record.t, true);
  gauss_newton_sum_ += gaussNewton(error.residuals, factors_);
  steps_ = stepSizesFrom(gauss_newton_sum_.scaled(1.0 / record.t), settings_.step_rule, settings_.step_b,
                         settings_.step_scale);
  record.E = error.E;
  record.per_image = error.per_image;
  record.relative_errors = error.relative_errors;
  record.theta = factors_.parameters();
  record.gradient = factors_.chainRule(error.dE_de);
  const std::vector<double> change = steps_.update(record.gradient, record.t);
  record.step = steps_.diagonal(record.t);
  double longest = 0;
  for (std::size_t p = 0; p < change.size(); ++p) longest = std::max(longest, std::abs(change[p]) / record.theta[p]);
  double length = longest > kMaxRelativeChange ? kMaxRelativeChange / longest : 1.0;
  record.shortened = length < 1;
  // Feasibility (every effective albedo <= 1): a step that leaves it is shortened to stay inside
  // (bisection), rather than projected back by scaling a whole cluster down, which would turn a
  // change of lobe balance into a loss of brightness.
  const auto stepped = [&](double a) {
    WeightFactors f = factors_;
    std::vector<double> t = record.theta;
    for (std::size_t p = 0; p < t.size(); ++p) t[p] = std::max(kMinFactor, t[p] - a * change[p]);  // Eq. 17
    f.setParameters(t);
    return f;
  };
  if (!isFeasible(layout_, stepped(length)) && isFeasible(layout_, factors_)) {
    double inside = 0, outside = length;
    for (int i = 0; i < 30; ++i) {
      const double middle = (inside + outside) / 2;
      (isFeasible(layout_, stepped(middle)) ? inside : outside) = middle;
    }
    length = inside;
    record.limited = true;
  }
  factors_ = stepped(length);
  record.limited |= constrainFactors(layout_, factors_);
  const std::vector<double> updated = factors_.parameters();
  for (std::size_t p = 0; p < updated.size(); ++p)
    record.relative_change = std::max(record.relative_change, std::abs(updated[p] - record.theta[p]) / record.theta[p]);
  record.seconds = clock.seconds();
  history_.push_back(std::move(record));
  return history_.back();
}

bool WeightOptimizer::converged() const {
  constexpr int kWindow = 3;
  if (iteration() < std::max(settings_.min_iterations, kWindow)) return false;
  for (int i = iteration() - kWindow; i < iteration(); ++i)
    if (!(history_[i].relative_change < settings_.tolerance)) return false;
  return true;
}

namespace {

constexpr const char* kCheckpointFormat = "vdbappear-optimize-checkpoint";
constexpr int kCheckpointVersion = 1;

nlohmann::json recordJson(const IterationRecord& r) {
  return {{"t", r.t},       {"E", r.E},         {"theta", r.theta},     {"gradient", r.gradient},
          {"step", r.step}, {"limited", r.limited}, {"shortened", r.shortened}, {"relative_change", r.relative_change}, {"seconds", r.seconds},
          {"per_image", r.per_image}};
}

IterationRecord recordOf(const nlohmann::json& j) {
  IterationRecord r;
  r.t = intOf(j.at("t"), "history: t");
  r.E = j.at("E").get<double>();
  r.theta = j.at("theta").get<std::vector<double>>();
  r.gradient = j.at("gradient").get<std::vector<double>>();
  r.step = j.at("step").get<std::vector<double>>();
  r.limited = j.at("limited").get<bool>();
  r.shortened = j.at("shortened").get<bool>();
  r.relative_change = j.at("relative_change").get<double>();
  r.seconds = j.at("seconds").get<double>();
  r.per_image = j.at("per_image").get<std::vector<double>>();
  return r;
}

}  // namespace

nlohmann::json WeightOptimizer::checkpoint(const nlohmann::json& inputs) const {
  nlohmann::json history = nlohmann::json::array();
  for (const IterationRecord& r : history_) history.push_back(recordJson(r));
  return {{"format", kCheckpointFormat}, {"format_version", kCheckpointVersion}, {"version", kVersion},
          {"inputs", inputs},            {"iteration", iteration()},           {"factors", factors_.toJson()},
          {"steps", steps_.toJson()},    {"gauss_newton_sum", {{"H", gauss_newton_sum_.H}, {"D", gauss_newton_sum_.D}}}, {"history", history}};
}

void WeightOptimizer::resume(const nlohmann::json& checkpoint, const nlohmann::json& inputs) {
  try {
    if (!checkpoint.is_object() || checkpoint.value("format", "") != kCheckpointFormat)
      throw std::invalid_argument("not a checkpoint of vdb_optimize_weights");
    const int format_version = intOf(checkpoint.at("format_version"), "format_version");
    if (format_version != kCheckpointVersion || checkpoint.at("version").get<std::string>() != kVersion)
      throw std::invalid_argument(fmt::format("written by vdbappear {} (checkpoint format {}), this is {} (format {})",
                                              checkpoint.at("version").get<std::string>(),
                                              format_version, kVersion, kCheckpointVersion));
    if (checkpoint.at("inputs") != inputs)
      throw std::invalid_argument("made with other inputs or settings (media, training set, seed, mode or spp differ)");
    WeightFactors factors = WeightFactors::fromJson(checkpoint.at("factors"));
    if (factors.clusters() != factors_.clusters() || factors.lobes() != factors_.lobes() || factors.mode() != factors_.mode())
      throw std::invalid_argument("its factors do not fit this medium");
    std::vector<IterationRecord> history;
    for (const nlohmann::json& r : checkpoint.at("history")) history.push_back(recordOf(r));
    if (int(history.size()) != intOf(checkpoint.at("iteration"), "iteration")) throw std::invalid_argument("its history is incomplete");
    StepSizes steps = history.empty() ? StepSizes() : StepSizes::fromJson(checkpoint.at("steps"));
    GaussNewton gauss_newton_sum;
    gauss_newton_sum.H = checkpoint.at("gauss_newton_sum").at("H").get<std::vector<double>>();
    gauss_newton_sum.D = checkpoint.at("gauss_newton_sum").at("D").get<std::vector<double>>();
    const std::size_t P = std::size_t(factors.parameterCount());
    if (!history.empty() && (steps.parameters() != int(P) || gauss_newton_sum.H.size() != P * P ||
                             gauss_newton_sum.D.size() != P))
      throw std::invalid_argument("its step sizes do not fit the factors");
    factors_ = std::move(factors);
    steps_ = std::move(steps);
    history_ = std::move(history);
    gauss_newton_sum_ = std::move(gauss_newton_sum);
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("malformed checkpoint: ") + e.what());
  }
}

}  // namespace vdbappear
