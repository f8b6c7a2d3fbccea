#include "libvdbappear/lobes/multi_lobe_downsample.h"

#include "libvdbappear/lobes/multi_lobe_stages.h"
#include "libvdbappear/util/progress.h"

#include <cmath>

namespace vdbappear {

double LobeFitStatistics::relativeError(int m) const {
  return squared_target > 0 ? std::sqrt(squared_error.at(m - 1) / squared_target) : 0.0;
}

int LobeFitStatistics::ruleLobeCount(double keep_ratio) const {
  int m = 1;
  while (m < int(squared_error.size()) && squared_error[m - 1] > 0 &&
         std::sqrt(squared_error[m]) <= keep_ratio * std::sqrt(squared_error[m - 1]))
    ++m;
  return m;
}

// The whole medium as one part (lobes/multi_lobe_stages.h).
MultiLobeResult downsampleMultiLobe(const Medium& fine, const MultiLobeOptions& options, ProgressBar* progress) {
  MultiLobeStages stages(options);
  MediumPtr coarse = stages.coarsePart(fine);
  if (progress) progress->setTotal(2 * coarse->density->tree().leafCount());
  stages.fitPart(fine, *coarse, progress);
  stages.cluster();
  stages.pickReferences(*coarse);
  stages.orderPart(*coarse, progress);
  return stages.result(coarse);
}

}  // namespace vdbappear
