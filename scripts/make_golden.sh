#!/usr/bin/env bash
# Regenerates the golden grids in grids/golden/ from this build. Run it only when a change of
# results is intended, and say why in the commit. Each file's `history` metadata holds the command
# that made it: tests/cli/golden_media_test.cpp re-runs those commands and compares the grids, and
# tests/unit/golden_test.cpp checks the downsampling of twill24.vdb.
# Usage: scripts/make_golden.sh [BUILD_DIR]
set -euo pipefail
build=$(realpath "${1:-build}")
cd "$(dirname "$0")/../grids/golden"
rm -f ./*.vdb
make="$build/bin/vdb_make_medium"
# Run by name so that the history line reads "vdb_make_medium ...".
PATH="$build/bin:$PATH"
vdb_make_medium twill --res 24 --seed 1 -o twill24.vdb
vdb_make_medium velvet --res 16 --yarns 2 --seed 1 -o velvet16.vdb
vdb_make_medium hairy-ball --res 16 --two-materials --seed 1 -o hairy-ball16.vdb
vdb_make_medium cube --res 8 --phase sggx-fiber --axis 1,1,0 --variation 0.5 -o cube8.vdb
vdb_make_medium sphere --res 8 --phase hg --g 0.8 --albedo 0.9,0.6,0.3 -o sphere8.vdb
vdb_make_medium slab --res 8 --density 4 -o slab8.vdb
vdb_make_medium cloud --res 16 --seed 1 -o cloud16.vdb
vdb_make_medium exemplars --res 8 --count 3 --layout 4x4 --seed 1 -o exemplars8.vdb
vdb_sggx_downsample --factor 2 twill24.vdb twill24_naive2x.vdb
ls -l
du -ch ./*.vdb | tail -1
