#!/usr/bin/python3
"""Independent check of vdb_render's extinction: the mean transmittance of a medium seen by a pinhole
camera, by quadrature of the trilinearly interpolated density along every pixel's rays.

Render the medium with albedo 0 under --env 1 (vdb_make_medium ... --warp-albedo 0 --weft-albedo 0, or
--albedo 0) with `vdb_render --interp trilinear --report R.json`: every pixel is then the transmittance
along its ray, and the image mean must match this script's within Monte Carlo error. Reads the camera
and resolution from R.json; S is taken as I (vdb_render --no-sggx), the quadrature uses STEPS samples per
ray between the planes bounding the medium's active voxels in z (so: for views along z, --view +z or -z).

Benchmark and diagnosis only: needs Debian's python3-openvdb and numpy (hence /usr/bin/python3).
Usage: scripts/check_transmittance.py MEDIUM.vdb R.json [--steps 1024] [--jitter 4] [--seed 1]
"""
import argparse
import json
import math

import numpy as np
import pyopenvdb as vdb


def trilinear(grid_array, p):
    """Density at index-space points p (..., 3) of a dense array whose element [0,0,0] is at index 0;
    zero outside (inactive voxels are empty, as in vdb_render)."""
    i = np.floor(p).astype(np.int64)
    f = p - i
    inside = (i >= 0).all(-1) & (i < np.array(grid_array.shape) - 1).all(-1)
    i = np.where(inside[..., None], i, 0)
    value = np.zeros(p.shape[:-1])
    for c in range(8):
        o = [(c >> a) & 1 for a in range(3)]
        w = np.ones(p.shape[:-1])
        for a in range(3):
            w *= f[..., a] if o[a] else 1 - f[..., a]
        value += w * grid_array[i[..., 0] + o[0], i[..., 1] + o[1], i[..., 2] + o[2]]
    return np.where(inside, value, 0.0)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("medium")
    p.add_argument("report")
    p.add_argument("--steps", type=int, default=1024)
    p.add_argument("--jitter", type=int, default=4, help="jittered rays per pixel")
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    density = vdb.read(a.medium, "density")
    (x0, y0, z0), (x1, y1, z1) = density.evalActiveVoxelBoundingBox()
    pad = 2
    origin = np.array([x0 - pad, y0 - pad, z0 - pad])
    dense = np.zeros((x1 - x0 + 1 + 2 * pad, y1 - y0 + 1 + 2 * pad, z1 - z0 + 1 + 2 * pad), np.float32)
    density.copyToArray(dense, ijk=tuple(int(v) for v in origin))
    voxel = np.array(density.transform.voxelSize())
    offset = np.array(density.transform.indexToWorld((0, 0, 0)))  # world = index * voxel + offset
    zmin, zmax = offset[2] + (z0 - 1) * voxel[2], offset[2] + (z1 + 1) * voxel[2]

    report = json.loads(open(a.report).read())
    cam = report["camera"]
    width, height = report["resolution"]
    pos, target, up = (np.array(cam[k], float) for k in ("position", "target", "up"))
    forward = (target - pos) / np.linalg.norm(target - pos)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    tan_half = math.tan(math.radians(cam["fov"]) / 2)
    rng = np.random.default_rng(a.seed)
    x, y = np.meshgrid(np.arange(width), np.arange(height))
    means = []
    for _ in range(a.jitter):
        sx = (2 * (x + rng.random(x.shape)) / width - 1) * tan_half * width / height
        sy = (1 - 2 * (y + rng.random(y.shape)) / height) * tan_half
        d = forward + sx[..., None] * right + sy[..., None] * true_up
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        t0 = (np.where(d[..., 2] < 0, zmax, zmin) - pos[2]) / d[..., 2]
        t1 = (np.where(d[..., 2] < 0, zmin, zmax) - pos[2]) / d[..., 2]
        tau = np.zeros(x.shape)
        for k in range(a.steps):
            t = t0 + (k + 0.5) / a.steps * (t1 - t0)
            world = pos + d * t[..., None]
            tau += trilinear(dense, (world - offset) / voxel - origin) * (t1 - t0) / a.steps
        means.append(float(np.exp(-tau).mean()))
    print(json.dumps({"mean_transmittance": float(np.mean(means)), "per_jitter": means,
                      "vdb_render_mean": report.get("mean_pixel_value")}))


if __name__ == "__main__":
    main()
