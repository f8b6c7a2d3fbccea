// libFuzzer harness: checkpoints of vdb_optimize_weights (--resume), resumed into an optimiser of
// 2 clusters, 2 lobes and colour scales (the seed's). The inputs a checkpoint must match are
// compared as a whole; the harness passes the checkpoint's own, so that mutations reach the parsing
// of the factors, the history and the step sizes. The tool names the file in what resume() throws
// (std::invalid_argument); any other exception would reach the user without it: a finding.
#include "libvdbappear/optimize/training_images.h"
#include "libvdbappear/optimize/weight_optimizer.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace {

using namespace vdbappear;

LobeMediumLayout twoClustersTwoLobes() {
  LobeMediumLayout layout;
  layout.clusters = 2;
  layout.lobes = 2;
  layout.naive_weights.resize(2);  // no voxels: the albedo limit never binds
  layout.coloured = true;
  return layout;
}

OptimizerSettings colourScales() {
  OptimizerSettings settings;
  settings.mode = ColourMode::kColourScales;
  return settings;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json checkpoint;
  try {
    checkpoint = nlohmann::json::parse(data, data + size);
  } catch (const nlohmann::json::exception&) {
    return 0;  // the tool: "FILE: not a complete checkpoint (truncated or not JSON)"
  }
  const nlohmann::json inputs = checkpoint.is_object() && checkpoint.contains("inputs") ? checkpoint["inputs"] : nlohmann::json();
  TrainingScenes scenes(nullptr, {});
  WeightOptimizer optimizer(scenes, {}, twoClustersTwoLobes(), colourScales());
  try {
    optimizer.resume(checkpoint, inputs);
  } catch (const std::invalid_argument&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz harness: resume() threw past the tool's handler: %s\n", e.what());
    std::abort();
  }
  return 0;
}
