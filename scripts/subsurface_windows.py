"""Window means of the physical check's renders (make subsurface, scripts/subsurface_experiment.py):
the multiple-scattering image MS = FULL - SINGLE of the path-traced cube, written as a PFM, and the
means of FULL, SINGLE, MS and the dipole's image over square windows given as image fractions (x, y from the top
left, half-width h).

Run under Blender, which reads and writes OpenEXR:
  blender -b -noaudio --factory-startup --python-exit-code 1 -P scripts/subsurface_windows.py -- \\
      FULL.exr SINGLE.exr DIPOLE.exr MS_OUT.pfm NAME:X:Y:H [NAME:X:Y:H ...]
Prints one JSON line on stdout that starts with '{': {NAME: {"full", "single", "ms", "dipole": means}, ...}.
"""
import json
import os
import struct
import sys

import bpy


def load(path):
    image = bpy.data.images.load(os.path.abspath(path))
    return image.size[0], image.size[1], list(image.pixels[:])


def write_pfm(path, w, h, rgba):
    """A colour PFM (linear floats; rows bottom to top, as Blender holds them). Blender's own image
    save applies its colour management to generated images, so it is not used."""
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        rgb = [v for i, v in enumerate(rgba) if i % 4 != 3]
        f.write(struct.pack("<%df" % len(rgb), *rgb))


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    (w, h, full), (_, _, single), (_, _, dipole) = (load(p) for p in args[:3])
    ms = [f - s if i % 4 != 3 else 1.0 for i, (f, s) in enumerate(zip(full, single))]
    write_pfm(args[3], w, h, ms)
    result = {}
    for spec in args[4:]:
        name, fx, fy, fh = spec.split(":")
        fx, fy, fh = float(fx), float(fy), float(fh)
        sums = {"full": 0.0, "single": 0.0, "ms": 0.0, "dipole": 0.0}
        n = 0
        for y in range(h):
            for x in range(w):
                u, v = (x + 0.5) / w, 1 - (y + 0.5) / h  # Blender's rows run bottom to top
                if abs(u - fx) <= fh and abs(v - fy) <= fh:
                    i = 4 * (y * w + x)
                    sums["full"] += sum(full[i:i + 3]) / 3
                    sums["single"] += sum(single[i:i + 3]) / 3
                    sums["ms"] += sum(ms[i:i + 3]) / 3
                    sums["dipole"] += sum(dipole[i:i + 3]) / 3
                    n += 1
        result[name] = {k: v / n for k, v in sums.items()} if n else {}
    print(json.dumps(result))


main()
