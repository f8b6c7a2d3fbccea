#!/usr/bin/env bash
# Regenerates the golden grids in grids/golden/ from this build. Run it only when a change of
# results is intended, and say why in the commit; tests/unit/golden_test.cpp compares against them.
# Usage: scripts/make_golden.sh [BUILD_DIR]
set -euo pipefail
build=${1:-build}
golden="$(dirname "$0")/../grids/golden"
"$build/bin/vdb_make_medium" twill --pattern plain --res 24 --seed 1 -o "$golden/weave24.vdb"
"$build/bin/vdb_sggx_downsample" --factor 2 "$golden/weave24.vdb" "$golden/weave24_naive2x.vdb"
ls -l "$golden"
