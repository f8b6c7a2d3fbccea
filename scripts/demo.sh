#!/usr/bin/env bash
# `make demo`: the main job on the built-in default medium. Makes the two-coloured twill in code,
# downsamples it naively by 2, 4 and 8, draws a preview of each, and reports voxel counts, bytes
# and timings (printed, and written to demo-out/report.md with the JSON reports and PNGs beside it).
# Usage: scripts/demo.sh [BUILD_DIR]   (environment: DEMO_OUT=folder, DEMO_RES=voxels)
set -euo pipefail
build=${1:-build}
out=${DEMO_OUT:-demo-out}
res=${DEMO_RES:-256}
bin="$build/bin"
mkdir -p "$out"

echo "demo: making the default medium (two-coloured twill, ${res} voxels across)"
start=$(date +%s.%N)
"$bin/vdb_make_medium" twill --res "$res" --seed 1 -o "$out/twill.vdb"
end=$(date +%s.%N)
python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.3f}')" "$start" "$end" > "$out/make_seconds.txt"

for factor in 2 4 8; do
  echo "demo: vdb_sggx_downsample --factor $factor"
  "$bin/vdb_sggx_downsample" --factor "$factor" --report "$out/twill_${factor}x.json" \
    "$out/twill.vdb" "$out/twill_${factor}x.vdb"
done
echo "demo: previews (vdb_preview: absorption-emission, not a renderer)"
"$bin/vdb_preview" --width 480 "$out/twill.vdb" -o "$out/twill.png"
for factor in 2 4 8; do
  "$bin/vdb_preview" --width 480 "$out/twill_${factor}x.vdb" -o "$out/twill_${factor}x.png"
done
python3 "$(dirname "$0")/demo_report.py" "$out"
