#!/usr/bin/python3
"""Copy a medium and add the scattering coefficient sigma_s = density * albedo as three FloatGrids
"sigma_s_r", "sigma_s_g", "sigma_s_b", for renderers that interpolate each grid on its own (Blender
Cycles).

Why: vdb_render's trilinear lookup weights albedo by density (sigma_s = trilinear(rho * albedo),
docs/rendering.md). A renderer that interpolates "albedo" and "density" separately and multiplies
them mixes the albedo of the empty voxels around a fibre (the grid's background) into the fibre's
edge, and renders a different medium. Given "sigma_s", scripts/blender_scene.py builds the same
coefficients as vdb_render: sigma_s = trilinear(rho * albedo), sigma_a = trilinear(rho) - sigma_s.

Benchmark only (scripts/bench_render.py): needs Debian's python3-openvdb (pyopenvdb) and numpy,
hence /usr/bin/python3 rather than whatever python3 comes first on PATH.

Benchmark and make interop only (scripts/bench_render.py, scripts/interop_experiment.py).

Usage: scripts/premultiply_albedo.py IN.vdb OUT.vdb [--albedo GRID]
  --albedo GRID: the albedo's grid (default "albedo"; "Cd" for a Houdini file, which the tools' Houdini
  preset reads as the albedo)
"""
import sys

import numpy as np
import pyopenvdb as vdb


def fail(message):
    print("premultiply_albedo.py: error: " + message, file=sys.stderr)
    sys.exit(2)


def main():
    args = sys.argv[1:]
    albedo_name = "albedo"
    if "--albedo" in args:
        k = args.index("--albedo")
        if k + 1 >= len(args):
            fail("--albedo needs a grid name")
        albedo_name = args[k + 1]
        del args[k:k + 2]
    if len(args) != 2:
        fail("usage: premultiply_albedo.py IN.vdb OUT.vdb [--albedo GRID]")
    src, dst = args
    grids, metadata = vdb.readAll(src)
    by_name = {g.name: g for g in grids}
    if "density" not in by_name:
        fail(f"{src}: no grid named 'density'")
    density = by_name["density"]
    albedo = by_name.get(albedo_name)  # none: albedo 1
    if albedo is None and albedo_name != "albedo":
        fail(f"{src}: no grid named '{albedo_name}'")
    (x0, y0, z0), (x1, y1, z1) = density.evalActiveVoxelBoundingBox()
    shape = (x1 - x0 + 1, y1 - y0 + 1, z1 - z0 + 1)
    rho = np.zeros(shape, dtype=np.float32)
    density.copyToArray(rho, ijk=(x0, y0, z0))
    if albedo is None:
        a = np.ones(shape + (3,), dtype=np.float32)
    elif isinstance(albedo, vdb.FloatGrid):
        a = np.zeros(shape, dtype=np.float32)
        albedo.copyToArray(a, ijk=(x0, y0, z0))
        a = np.repeat(a[..., None], 3, axis=-1)
    else:
        a = np.zeros(shape + (3,), dtype=np.float32)
        albedo.copyToArray(a, ijk=(x0, y0, z0))
    # copyToArray fills inactive voxels with the background: density 0 there, so sigma_s is 0 too.
    # One float grid per channel: Cycles 3.4 samples Vec3 grids at other points than float grids.
    channels = []
    for c, name in enumerate(("sigma_s_r", "sigma_s_g", "sigma_s_b")):
        sigma_s = vdb.FloatGrid(background=0.0)
        sigma_s.copyFromArray(np.ascontiguousarray(rho * a[..., c]), ijk=(x0, y0, z0), tolerance=0.0)
        sigma_s.name = name
        sigma_s.transform = density.transform
        channels.append(sigma_s)
    vdb.write(dst, grids=grids + channels, metadata=metadata)


if __name__ == "__main__":
    main()
