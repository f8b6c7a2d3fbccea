#!/usr/bin/env bash
# `make demo`: the main job on the built-in default medium. Makes the two-coloured twill in code,
# downsamples it naively by 2, 4 and 8 (Eq. 5-6) and by 4 with 2 SGGX lobes per voxel (§5), optimises
# that reduction's lobe weights (vdb_optimize_weights, §6.3-6.4), renders each with vdb_render under one camera and
# lights, and compares every reduction with the full-resolution render: side-by-side pictures with
# a false-colour relative-error map, and the mean-intensity error over the fabric's pixels (the
# brightening of Fig. 1 of the downsampling paper). Everything lands in demo-out/ (report.md,
# JSON reports, EXR and PNG images).
# Usage: scripts/demo.sh [BUILD_DIR]   (environment: DEMO_OUT=folder, DEMO_RES=voxels, DEMO_SPP=samples)
set -euo pipefail
build=${1:-build}
out=${DEMO_OUT:-demo-out}
res=${DEMO_RES:-384}
spp=${DEMO_SPP:-48}
bin="$build/bin"
mkdir -p "$out"

echo "demo: making the default medium (two-coloured twill, 12 yarns, ${res} voxels across)"
start=$(date +%s.%N)
"$bin/vdb_make_medium" twill --yarns 12 --res "$res" --seed 1 -o "$out/twill.vdb"
end=$(date +%s.%N)
python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.3f}')" "$start" "$end" > "$out/make_seconds.txt"

for factor in 2 4 8; do
  echo "demo: vdb_sggx_downsample --factor $factor"
  "$bin/vdb_sggx_downsample" --factor "$factor" --report "$out/twill_${factor}x.json" \
    "$out/twill.vdb" "$out/twill_${factor}x.vdb"
done

# One oblique camera over the 12 x 12 world-unit sheet, a sky and a low sun, a grey ground.
echo "demo: vdb_lobe_cluster --factor 4 --lobes 2 --clusters 2 (2 SGGX lobes per voxel, naive weights)"
"$bin/vdb_lobe_cluster" --factor 4 --lobes 2 --clusters 2 --report "$out/twill_4x_lobes.json" \
  "$out/twill.vdb" "$out/twill_4x_lobes.vdb"

echo "demo: vdb_optimize_weights (SGD on the lobe-weight factors, §6.3-6.4; references cached in $out/cache)"
"$bin/vdb_optimize_weights" --cache "$out/cache" --log "$out/optimize.jsonl" --report "$out/twill_4x_optimised.json" \
  "$out/twill.vdb" "$out/twill_4x_lobes.vdb" "$out/twill_4x_optimised.vdb"

# The ground under the full-resolution fabric for every medium (a reduction's own box is rounded
# outward, and vdb_render's default ground follows the medium's box).
bottom=$("$bin/vdb_render" "$out/twill.vdb" -o "$out/probe.png" --res 8 --spp 1 --report - |
         python3 -c "import json, sys; print(json.load(sys.stdin)['bounds'][0][2])")
rm -f "$out/probe.png"
scene=(--camera-pos 6,-6,9 --camera-target 6,5,0.5 --fov 45 --res 320x240 --spp "$spp" --seed 1
       --env 0.25 --sun 1,0.6,-1.2,3 --ground --ground-height "$bottom" --aov alpha,variance)
for name in twill twill_2x twill_4x twill_4x_lobes twill_4x_optimised twill_8x; do
  echo "demo: vdb_render $name.vdb ($spp spp)"
  "$bin/vdb_render" "$out/$name.vdb" -o "$out/render_$name.exr" --preview "$out/render_$name.png" \
    --report "$out/render_$name.json" "${scene[@]}"
done
for reduced in 2x 4x 4x_lobes 4x_optimised 8x; do
  "$bin/vdb_image_compare" "$out/render_twill.exr" "$out/render_twill_${reduced}.exr" --foreground --range 0.5 \
    --side-by-side "$out/compare_${reduced}.png" --error-map "$out/error_${reduced}.png" \
    --report "$out/compare_${reduced}.json"
  "$bin/vdb_image_compare" "$out/render_twill.exr" "$out/render_twill_${reduced}.exr" --foreground --tile 8 \
    --report "$out/compare_${reduced}_tiles.json"
done
python3 "$(dirname "$0")/demo_report.py" "$out"
