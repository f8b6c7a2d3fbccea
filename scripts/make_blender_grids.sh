#!/bin/sh
# The foreign files of grids/blender/, baked with Debian's Blender 3.4 (scripts/bake_blender.py):
# a Mantaflow smoke and a Mantaflow fire, frame 24 of 32 voxels. Regenerate only to change them,
# and say why in the commit; the tests read the files as they are (grids/README.md).
set -eu
cd "$(dirname "$0")/.."
command -v blender >/dev/null || { echo "make_blender_grids.sh: needs Debian's blender (apt-get install blender)" >&2; exit 1; }
# Mantaflow writes waveletNoiseTile.bin into the working directory: run Blender in a temporary one.
repo=$(pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for style in smoke fire; do
  (cd "$work" && blender -b -noaudio --factory-startup --python-exit-code 1 -P "$repo/scripts/bake_blender.py" -- \
    --style "$style" --frame 24 --resolution 32 --out "$repo/grids/blender/${style}24.vdb" 2>&1) | grep '^bake_blender.py' >&2
done
