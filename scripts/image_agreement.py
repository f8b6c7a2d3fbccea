"""Do two renderers' images agree within Monte Carlo error, pixel by pixel? Each renderer gives two
renders of the same scene with different seeds (A1, A2 and B1, B2). Per pixel and channel,
D = (A1 + A2)/2 - (B1 + B2)/2 has variance var = ((A1 - A2)^2 + (B1 - B2)^2) / 4 in expectation, so:

* "variance_ratio" = sum D^2 / sum var is 1 for agreeing images, more where they differ;
* the same over TILE x TILE tiles (default 8; sums make the variance estimate steadier): the z-score
  of each tile and channel, z = sum D / sqrt(sum var), should be standard normal: "tile_z_mean" near 0,
  "tile_z_rms" near 1, and "tile_z_over_4" (|z| > 4) near 0 out of "tiles".

Run under Blender, which reads OpenEXR and has numpy (scripts/bench_render.py does):
  blender -b -noaudio --factory-startup --python-exit-code 1 -P scripts/image_agreement.py -- \\
      A1.exr A2.exr B1.exr B2.exr [--tile 8]
Prints one JSON line on stdout that starts with '{'.
"""
import json
import math
import os
import sys

import bpy  # no numpy: Blender started from another Python (pyenv) may not find Debian's


def load(path):
    """(width, height, flat RGBA list) of an image; Blender reads relative paths as blend-file relative."""
    image = bpy.data.images.load(os.path.abspath(path))
    return image.size[0], image.size[1], list(image.pixels[:])


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    tile = 8
    if "--tile" in args:
        k = args.index("--tile")
        tile = int(args[k + 1])
        del args[k:k + 2]
    if len(args) != 4:
        print("usage: image_agreement.py -- A1.exr A2.exr B1.exr B2.exr [--tile 8]", file=sys.stderr)
        sys.exit(2)
    images = [load(p) for p in args]
    width, height = images[0][0], images[0][1]
    if any((w, h) != (width, height) for w, h, _ in images):
        print("image_agreement.py: the images differ in size", file=sys.stderr)
        sys.exit(2)
    a1, a2, b1, b2 = (pixels for _, _, pixels in images)
    tiles_x, tiles_y = width // tile, height // tile
    d_tiles = [0.0] * (tiles_x * tiles_y * 3)
    var_tiles = [0.0] * (tiles_x * tiles_y * 3)
    d2_sum = var_sum = 0.0
    for y in range(height):
        for x in range(width):
            for c in range(3):
                i = 4 * (y * width + x) + c
                d = (a1[i] + a2[i]) / 2 - (b1[i] + b2[i]) / 2
                var = ((a1[i] - a2[i]) ** 2 + (b1[i] - b2[i]) ** 2) / 4
                d2_sum += d * d
                var_sum += var
                if x // tile < tiles_x and y // tile < tiles_y:
                    t = 3 * ((y // tile) * tiles_x + x // tile) + c
                    d_tiles[t] += d
                    var_tiles[t] += var
    z = [d / math.sqrt(v) for d, v in zip(d_tiles, var_tiles) if v > 0]
    print(json.dumps({"variance_ratio": d2_sum / var_sum if var_sum > 0 else float("nan"), "tile": tile,
                      "tiles": len(z), "tile_z_mean": sum(z) / len(z) if z else float("nan"),
                      "tile_z_rms": math.sqrt(sum(v * v for v in z) / len(z)) if z else float("nan"),
                      "tile_z_over_4": sum(1 for v in z if abs(v) > 4)}))


main()
