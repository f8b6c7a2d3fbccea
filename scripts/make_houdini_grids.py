#!/usr/bin/python3
"""The Houdini-convention file of grids/houdini/: Blender's fire (grids/blender/fire24.vdb) with its grids
under the names Houdini's Pyro solver writes, and a colour, so that the tools meet a `Cd` and a `vel`.

  density      <- density
  Cd           (vec3s, new) a smoke colour: warm near the source, grey above it (Houdini's pyro writes
               Cd as the smoke's colour; the tools' Houdini preset reads it as the albedo)
  temperature  <- temperature
  flame        <- flame
  vel          <- velocity
  (shadow, Mantaflow's own, is left out)

Cd is defined on the density's active voxels: a blend from (0.95, 0.55, 0.25) at the lowest voxel to
(0.7, 0.7, 0.75) at the highest, linear in the voxel's height. The file is not written by Houdini: it
holds Houdini's names and types (the conventions docs/medium.md section 12 describes), which is what
the tools read. Regenerate only to change it, and say why in the commit (grids/README.md).

Needs Debian's python3-openvdb (pyopenvdb) and python3-numpy, installed with apt when missing.
Usage: scripts/make_houdini_grids.py [IN.vdb] [OUT.vdb]
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
try:
    import numpy as np
    import pyopenvdb as vdb
except ImportError:
    from debian_packages import apt_install
    apt_install(["python3-openvdb", "python3-numpy"], "for scripts/make_houdini_grids.py")
    os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)

RENAMES = {"density": "density", "temperature": "temperature", "flame": "flame", "velocity": "vel"}
LOW, HIGH = np.array([0.95, 0.55, 0.25]), np.array([0.7, 0.7, 0.75])


def fail(message):
    print("make_houdini_grids.py: error: " + message, file=sys.stderr)
    sys.exit(2)


def colour_grid(density):
    """Cd over the density's active voxels, blended by height (module doc)."""
    (x0, y0, z0), (x1, y1, z1) = density.evalActiveVoxelBoundingBox()
    shape = (x1 - x0 + 1, y1 - y0 + 1, z1 - z0 + 1)
    rho = np.zeros(shape, dtype=np.float32)
    density.copyToArray(rho, ijk=(x0, y0, z0))
    height = np.linspace(0.0, 1.0, shape[2]) if shape[2] > 1 else np.zeros(1)
    colour = LOW[None, :] * (1 - height[:, None]) + HIGH[None, :] * height[:, None]  # (z, 3)
    cd = np.broadcast_to(colour[None, None, :, :], shape + (3,)).astype(np.float32).copy()
    cd[rho <= 0] = 0.0  # empty voxels stay inactive (tolerance 0 keeps only the values that differ)
    grid = vdb.Vec3SGrid(background=(0.0, 0.0, 0.0))
    grid.copyFromArray(cd, ijk=(x0, y0, z0), tolerance=(0.0, 0.0, 0.0))
    grid.name = "Cd"
    grid.transform = density.transform
    return grid


def main():
    root = os.path.dirname(HERE)
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "grids", "blender", "fire24.vdb")
    dst = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "grids", "houdini", "pyro24.vdb")
    grids, _ = vdb.readAll(src)
    by_name = {g.name: g for g in grids}
    missing = [name for name in RENAMES if name not in by_name]
    if missing:
        fail(f"{src}: no grid named {', '.join(missing)}")
    out = []
    for old, new in RENAMES.items():
        grid = by_name[old]
        grid.name = new
        out.append(grid)
    out.insert(1, colour_grid(by_name["density"]))
    os.makedirs(os.path.dirname(os.path.abspath(dst)), exist_ok=True)
    tmp = dst + ".tmp"
    vdb.write(tmp, grids=out, metadata={"creator": "vdbappear scripts/make_houdini_grids.py (Houdini's grid names)"})
    os.replace(tmp, dst)
    print(f"make_houdini_grids.py: wrote {dst}: " + ", ".join(g.name for g in out), file=sys.stderr)


if __name__ == "__main__":
    main()
