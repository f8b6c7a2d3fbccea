#pragma once
// The tools of this build, by absolute path and quoted for the shell: the VDB_* paths that
// tests/CMakeLists.txt defines for each command-line test program (never a tool found on PATH).

#include "cli/run_command.h"

#include <string>

namespace vdbappear::test {

#ifdef VDB_SGGX_DOWNSAMPLE
inline const std::string kDownsample = quote(VDB_SGGX_DOWNSAMPLE);
#endif
#ifdef VDB_LOBE_CLUSTER
inline const std::string kLobeCluster = quote(VDB_LOBE_CLUSTER);
#endif
#ifdef VDB_OPTIMIZE_WEIGHTS
inline const std::string kOptimize = quote(VDB_OPTIMIZE_WEIGHTS);
#endif
#ifdef VDB_EXEMPLAR_STACK
inline const std::string kStack = quote(VDB_EXEMPLAR_STACK);
#endif
#ifdef VDB_IMAGE_COMPARE
inline const std::string kCompare = quote(VDB_IMAGE_COMPARE);
#endif
#ifdef VDB_SIMILARITY
inline const std::string kSimilarity = quote(VDB_SIMILARITY);
#endif
#ifdef VDB_SH_LIGHTGRID
inline const std::string kLightGrid = quote(VDB_SH_LIGHTGRID);
#endif
#ifdef VDB_MAKE_MEDIUM
inline const std::string kMakeMedium = quote(VDB_MAKE_MEDIUM);
#endif
#ifdef VDB_INFO
inline const std::string kInfo = quote(VDB_INFO);
#endif
#ifdef VDB_MAKE_HEIGHT_MAP
inline const std::string kMakeMap = quote(VDB_MAKE_HEIGHT_MAP);
#endif
#ifdef VDB_DISPLACEMENT_PREFILTER
inline const std::string kPrefilter = quote(VDB_DISPLACEMENT_PREFILTER);
#endif
#ifdef VDB_PREVIEW
inline const std::string kPreview = quote(VDB_PREVIEW);
#endif
#ifdef VDB_RENDER
inline const std::string kRender = quote(VDB_RENDER);
#endif
#ifdef VDB_RENDER_WITHOUT_MPI
inline const std::string kRenderWithoutMpi = quote(VDB_RENDER_WITHOUT_MPI);
#endif
#ifdef VDB_OPTIMIZE_WEIGHTS_WITHOUT_MPI
inline const std::string kOptimizeWithoutMpi = quote(VDB_OPTIMIZE_WEIGHTS_WITHOUT_MPI);
#endif

}  // namespace vdbappear::test
