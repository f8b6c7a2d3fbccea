#include "libvdbappear/optimize/weight_factors.h"

#include "libvdbappear/util/json_int.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace vdbappear {

const char* colourModeName(ColourMode mode) {
  switch (mode) {
    case ColourMode::kGrey: return "grey";
    case ColourMode::kColourScales: return "colour-scales";
    case ColourMode::kPerChannel: return "per-channel";
  }
  return "?";
}

ColourMode parseColourMode(const std::string& name) {
  for (ColourMode mode : {ColourMode::kGrey, ColourMode::kColourScales, ColourMode::kPerChannel})
    if (name == colourModeName(mode)) return mode;
  throw std::invalid_argument("colour mode '" + name + "': expected grey, colour-scales or per-channel");
}

namespace {

// clusters, after checking (before anything is allocated) that the shape holds a factor.
int checkedClusters(int clusters, int lobes) {
  if (clusters < 1 || lobes < 1) throw std::invalid_argument("WeightFactors: needs at least one cluster and one lobe");
  return clusters;
}

}  // namespace

WeightFactors::WeightFactors(int clusters, int lobes, ColourMode mode)
    : clusters_(checkedClusters(clusters, lobes)), lobes_(lobes), mode_(mode),
      w_(std::size_t(clusters) * std::size_t(lobes), Rgb::Ones()), s_(std::size_t(clusters), Rgb::Ones()) {}

LobeWeightScales WeightFactors::scales() const {
  LobeWeightScales scales(clusters_, lobes_);
  for (int k = 0; k < clusters_; ++k)
    for (int j = 0; j < lobes_; ++j) scales.at(k, j) = s(k) * w(k, j);
  return scales;
}

int WeightFactors::parameterCount() const {
  const int per_cluster = mode_ == ColourMode::kPerChannel ? 3 * lobes_ : lobes_ + (mode_ == ColourMode::kColourScales ? 3 : 0);
  return clusters_ * per_cluster;
}

namespace {

// Visits the parameters in the order of WeightFactors::parameters(): visit(value&, name).
template <typename Factors, typename Visit>
void forEachParameter(Factors& f, Visit&& visit) {
  const char* channel[3] = {"R", "G", "B"};
  for (int k = 0; k < f.clusters(); ++k) {
    for (int j = 0; j < f.lobes(); ++j) {
      if (f.mode() == ColourMode::kPerChannel) {
        for (int c = 0; c < 3; ++c) visit(f.w(k, j)[c], fmt::format("w_{},{}.{}", k, j, channel[c]), k, j, c);
      } else {
        visit(f.w(k, j)[0], fmt::format("w_{},{}", k, j), k, j, -1);
      }
    }
    if (f.mode() == ColourMode::kColourScales)
      for (int c = 0; c < 3; ++c) visit(f.s(k)[c], fmt::format("s_{}.{}", k, channel[c]), k, -1, c);
  }
}

}  // namespace

std::vector<double> WeightFactors::parameters() const {
  std::vector<double> theta;
  forEachParameter(*this, [&](double value, const std::string&, int, int, int) { theta.push_back(value); });
  return theta;
}

void WeightFactors::setParameters(const std::vector<double>& theta) {
  if (int(theta.size()) != parameterCount()) throw std::invalid_argument("WeightFactors: wrong parameter count");
  std::size_t i = 0;
  forEachParameter(*this, [&](double& value, const std::string&, int k, int j, int c) {
    value = theta[i++];
    if (j >= 0 && c < 0) w(k, j) = Rgb::Constant(value);  // grey factors: every channel
  });
}

std::vector<std::string> WeightFactors::parameterNames() const {
  std::vector<std::string> names;
  forEachParameter(*this, [&](double, const std::string& name, int, int, int) { names.push_back(name); });
  return names;
}

std::vector<double> WeightFactors::chainRule(const std::vector<Rgb>& d, bool gauge) const {
  if (d.size() != w_.size()) throw std::invalid_argument("WeightFactors::chainRule: wrong size");
  std::vector<double> gradient;
  forEachParameter(*this, [&](double value, const std::string&, int k, int j, int c) {
    double sum = 0;
    if (j >= 0 && c < 0) sum = d[std::size_t(k) * lobes_ + j].sum();  // w_kj: every channel
    if (j >= 0 && c >= 0) sum = d[std::size_t(k) * lobes_ + j][c];     // w_kj^c
    if (j < 0)
      for (int l = 0; l < lobes_; ++l) sum += d[std::size_t(k) * lobes_ + l][c];  // s_k^c
    gradient.push_back(sum / value);
  });
  // Colour scales carry the brightness (normaliseColourScales): the w_k part of the gradient is
  // projected onto the tangent of prod_j w_kj = 1 (normal n_j = 1 / w_kj), so that s_k and w_k
  // share no direction.
  if (gauge && mode_ == ColourMode::kColourScales)
    for (int k = 0; k < clusters_; ++k) {
      double* g_k = &gradient[std::size_t(k) * (lobes_ + 3)];
      double g_n = 0, n_n = 0;
      for (int j = 0; j < lobes_; ++j) {
        g_n += g_k[j] / w(k, j)[0];
        n_n += 1 / (w(k, j)[0] * w(k, j)[0]);
      }
      for (int j = 0; j < lobes_; ++j) g_k[j] -= g_n / n_n / w(k, j)[0];
    }
  return gradient;
}

void WeightFactors::normaliseColourScales() {
  if (mode_ != ColourMode::kColourScales) return;
  for (int k = 0; k < clusters_; ++k) {
    double log_mean = 0;
    for (int j = 0; j < lobes_; ++j) log_mean += std::log(w(k, j)[0]) / lobes_;
    const double mean = std::exp(log_mean);
    if (!(mean > 0) || !std::isfinite(mean)) continue;
    for (int j = 0; j < lobes_; ++j) w(k, j) /= mean;
    s(k) *= mean;
  }
}

namespace {

nlohmann::json rgbJson(const Rgb& v) { return {v[0], v[1], v[2]}; }

Rgb rgbOf(const nlohmann::json& j) {
  if (!j.is_array() || j.size() != 3) throw std::invalid_argument("weight_factors: expected [r, g, b]");
  Rgb v;
  for (int c = 0; c < 3; ++c) {
    if (!j[c].is_number()) throw std::invalid_argument("weight_factors: expected numbers");
    v[c] = j[c].get<double>();
    if (!(v[c] > 0) || !std::isfinite(v[c])) throw std::invalid_argument("weight_factors: factors must be finite and > 0");
  }
  return v;
}

}  // namespace

nlohmann::json WeightFactors::toJson() const {
  nlohmann::json w = nlohmann::json::array(), s = nlohmann::json::array();
  for (int k = 0; k < clusters_; ++k) {
    nlohmann::json row = nlohmann::json::array();
    for (int j = 0; j < lobes_; ++j) row.push_back(rgbJson(this->w(k, j)));
    w.push_back(row);
    s.push_back(rgbJson(this->s(k)));
  }
  return {{"clusters", clusters_}, {"lobes", lobes_}, {"mode", colourModeName(mode_)}, {"w", w}, {"s", s}};
}

WeightFactors WeightFactors::fromJson(const nlohmann::json& json) {
  try {
    const int clusters = intOf(json.at("clusters"), "weight_factors: clusters");
    const int lobes = intOf(json.at("lobes"), "weight_factors: lobes");
    const nlohmann::json &w = json.at("w"), &s = json.at("s");
    // The arrays' sizes bound the counts before the factors are allocated.
    if (!w.is_array() || int(w.size()) != clusters || !s.is_array() || int(s.size()) != clusters)
      throw std::invalid_argument("weight_factors: 'w' and 's' need one entry per cluster");
    if (clusters > 0 && (!w[0].is_array() || int(w[0].size()) != lobes))
      throw std::invalid_argument("weight_factors: 'w' needs one RGB per lobe in each cluster");
    WeightFactors f(clusters, lobes, parseColourMode(json.at("mode").get<std::string>()));
    for (int k = 0; k < f.clusters_; ++k) {
      if (!w[k].is_array() || int(w[k].size()) != f.lobes_)
        throw std::invalid_argument("weight_factors: 'w' needs one RGB per lobe in each cluster");
      for (int j = 0; j < f.lobes_; ++j) f.w(k, j) = rgbOf(w[k][j]);
      f.s(k) = rgbOf(s[k]);
    }
    return f;
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("weight_factors: ") + e.what());
  }
}

}  // namespace vdbappear
