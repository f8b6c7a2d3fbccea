"""Bake one frame of a small Mantaflow smoke or fire with Blender and keep its OpenVDB cache file.

Run headless, never imported (scripts/make_blender_grids.sh runs it for grids/blender/):

  blender -b -noaudio --factory-startup --python-exit-code 1 -P scripts/bake_blender.py -- \
      --style fire|smoke --frame 24 --resolution 32 --out grids/blender/fire24.vdb

The scene is Blender's default cube made an emitter by Object > Quick Effects > Quick Smoke (style
'BOTH' for the fire, 'SMOKE' for the smoke), scaled to 0.3, in a domain of --resolution voxels along
its longest side, noise off. bpy.ops.fluid.bake_all() fails in background mode with Debian's
Blender 3.4, so the frames are stepped with the domain's cache type REPLAY, which bakes each frame as
the scene reaches it (docs/medium.md §12). The frame's file is the domain's data cache,
data/fluid_data_NNNN.vdb, copied as it is: the grids Mantaflow writes (density, flame, temperature,
shadow, velocity; no colour for these styles).
"""
import argparse
import pathlib
import shutil
import sys
import tempfile

import bpy


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="bake_blender.py")
    parser.add_argument("--style", choices=["fire", "smoke"], required=True)
    parser.add_argument("--frame", type=int, default=24)
    parser.add_argument("--resolution", type=int, default=32)
    parser.add_argument("--out", required=True)
    return parser.parse_args(argv)


def main():
    args = parse()
    cube = bpy.data.objects["Cube"]
    cube.scale = (0.3, 0.3, 0.3)
    bpy.ops.object.select_all(action="DESELECT")
    cube.select_set(True)
    bpy.context.view_layer.objects.active = cube
    bpy.ops.object.quick_smoke(style="BOTH" if args.style == "fire" else "SMOKE")
    domain = next(o for o in bpy.data.objects if o.name.startswith("Smoke Domain"))
    settings = domain.modifiers["Fluid"].domain_settings
    settings.resolution_max = args.resolution
    settings.use_noise = False
    settings.cache_type = "REPLAY"
    settings.cache_data_format = "OPENVDB"
    with tempfile.TemporaryDirectory() as cache:
        settings.cache_directory = cache
        for frame in range(1, args.frame + 1):
            bpy.context.scene.frame_set(frame)
        baked = pathlib.Path(cache) / "data" / f"fluid_data_{args.frame:04d}.vdb"
        if not baked.exists():
            print(f"bake_blender.py: error: Blender wrote no {baked.name}", file=sys.stderr)
            sys.exit(2)
        shutil.copyfile(baked, args.out)
    print(f"bake_blender.py: {args.out}: frame {args.frame} of a {args.style} at resolution {args.resolution}")


main()
