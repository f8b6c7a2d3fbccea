#!/usr/bin/env python3
"""Displacement-map prefiltering (issue 23, dissertation ch. 4), measured: `make displacement`.

For each surface (woven, noise and relief maps of vdb_make_height_map at --cells^2 cells on a plane;
"ball": its bumps map at --ball-cells^2 cells shell-mapped 8 x 4 times over a sphere, the ball of
Fig. 4.18, its models with the tables of its tiles squeezed toward the poles (--ball-stretches); "torus": the bumps map at --torus-cells^2 cells over a torus mesh by its UVs; on both curved bases S up to the view's horizon, which
their rims show, --curved-view-horizon), each
downsampling factor of --factors and the surface's own scale in the chapter (Table 4.3: woven 8x as
the twill, ball and torus 16x as the bump, noise 64x, relief 16x; unless --no-chapter-scales):
1. vdb_displacement_prefilter twice: with the shadowing-and-masking scaling R (Eq. 4.12, for direct
   light) and with the interreflection scaling R_ir (Eq. 4.20, for global illumination); its report
   gives the seconds of each step and the bytes of each part (Table 4.3-4.4).
2. Renders from a view and a sun that no step of the precomputation singles out (the tables cover
   every direction; this pair lies between their bins), under direct light (the sun, one bounce) and
   under global illumination (the sun and a sky, every bounce), of
     reference  the full-resolution map over the base BRDF (--spp-ref),
     naive      h_low over the base BRDF,
     multi-lobe h_low with f'_low alone (the scaling left out),
     full       h_low with f_low = T S f'_low,
   side by side with false-colour error maps (Fig. 4.16-4.17). The gate: the full model's relative
   error in mean intensity is at most one third of naive's and at most 3%. On the ball and the torus,
   the error split by region of the base surface: beyond the terminator (on the torus, or in its own
   shadow), under a grazing sun, under a high sun (on the torus, each on its outer, convex half and
   its inner, saddle half), past the silhouette (sphere_regions.py, torus_regions.py). With --lighting
   sun,sky besides gi, global illumination's error split by light: the sun and the sky each alone, every
   bounce, no gate of their own; the images add, so each error under gi is theirs weighted by each light's
   share, and the report shows where naive's errors under the two cancel. With --table-seeds 1,2,...,
   the full model's tables also made at each other seed and rendered: its error over them, each, their
   mean and its standard error (the tables' draw measured, for information; the gate judges seed 1's).
3. Equal time (Table 4.5): the original and the full model each rendered for --equal-time seconds
   under global illumination; their RMSE against the reference (rendered with another seed).
4. Level of detail (§4.7.2, Fig. 4.12, Table 4.5; the planar surfaces): the map tiled 4 x 4 and seen at a grazing angle,
   so that a pixel's footprint is 1.7 to 43 original cells of a 512^2 map wide by the square root of its
   area (twice as many at 1K^2; across the view 2 to 20 at 1K^2), under
   global illumination: the original at
   --lod-spp samples per pixel, and at the same render time the mipmap of the original and the
   R_ir models of --factors (each path on the level its pixel's footprint picks: by its width across
   the view, or with --lod-footprint area by the square root of its area) and the mipmap of
   the models alone; RMSE and mean error against the original at --lod-spp-ref (another seed), the
   mean error also by how steeply the view meets the tiles (plane_view_bands.py: near, middle, and
   beyond S's outermost bins, where --planar-view-horizon gives S its horizon nodes), and peak memory
   (/usr/bin/time -v).
5. Equal time where the chapter measures it (Table 4.5; the planar surfaces): a glossy base BRDF
   (GLOSSY) over --scale-tiles^2 tiles seen from afar, so that a pixel covers some 85 original cells
   of a 1K^2 map (2.7 coarse cells at 32x) and the original's highlights alias: its R_ir models at --factors,
   each rendered for the time the original takes at --scale-spp, against the original at
   --scale-spp-ref (another seed); RMSE, mean error and peak memory. The ball: the same base over
   its bumps map at --ball-scale-cells^2, for each count of --ball-scale-tiles T tiles around the
   equator (T x T/2 tiles, one tile's triangles per latitude band, the others turned copies of it),
   the sphere and the view of sections 1-2 scaled by T/8 and seen at --ball-scale-res: a pixel
   covers about 13 T/8 original cells where the ball faces the camera (T = 52: about the planar
   surfaces' 85; the chapter's ball, Table 4.3: its bumps map at 1K^2 over 4^2 tiles, at 16x).
Results: displacement-out/report.md and report.json, with the images.
Usage: scripts/displacement_experiment.py [--build build] [--out displacement-out] [--cells 1024]
        [--factors 8,32] [--surfaces woven,noise,relief,ball,torus] [--rates n15|quick|spread|chapter] [--lighting direct,gi[,sun,sky]]
        [--table-seeds 1[,2,...]] [--spp-ref 1024]
        [--spp 128] [--equal-time 10] [--res 192x144] [--lod-spp 16,64,256] [--lod-spp-ref 2048]
        [--ball-cells 1024] [--ball-stretches 0.75,0.5,0.3] [--curved-view-horizon 88] [--planar-view-horizon 0] [--lod-footprint narrow|area] [--no-curved-tables] [--periodic-tables none|tiled|all] [--relief-radius 2] [--torus-cells 128] [--scale-tiles 16] [--scale-spp 16,64] [--scale-spp-ref 2048]
        [--ball-scale-cells 512] [--ball-scale-tiles 8,52] [--ball-scale-res 128x96] [--resume] [--no-study]
        [--no-chapter-scales]
"""
import argparse
import functools
import json
import math
import pathlib
import statistics
import time

import plane_view_bands
import resumable
import sphere_regions
import table_draw
import torus_regions

BRDF = {"distribution": "ggx", "roughness": 0.3, "specular": 0.04, "diffuse": [0.7, 0.55, 0.4]}
# The chapter's sampling rates are the tool's defaults; the experiment's default is "n15" (every planar
# model within 0.9% in the full run of docs/displacement.md §9, against 1.9% quick); "quick" trades them for minutes (reported),
# and spends on positions per S bin what it saves on paths. S's bins are ratios over positions,
# which few bias bright: on the 1K^2 relief at 8x under direct light, +20.4% at the chapter's rates,
# +1.9% quick, -1.4% spread (positions converged, but N = 9 reads S 1-1.4% low between its bins),
# +0.35% n15 (N = 15, 1024 positions; -1.1% to +2.0% over three seeds, -1.3% and -0.8% with every
# coarse cell in each bin: one sun reads a few bins, whose noise moves the image;
# docs/displacement.md §9).
RATES = {"chapter": [],
         "quick": ["--paths", "64", "--angular-resolution", "9", "--pairs", "1000", "--positions", "256"],
         # The quick rates' paths per bin spread over 16 times the coarse cells (docs/displacement.md §9).
         "spread": ["--paths", "4", "--angular-resolution", "9", "--pairs", "16000", "--positions", "4096"],
         # The chapter's N = 15 (at N = 9 S's reading between bin centres left the noise 1.3% too
         # dark under the sun) with 1024 positions of 4 paths per S bin (docs/displacement.md §9).
         "n15": ["--paths", "4", "--angular-resolution", "15", "--pairs", "16000", "--positions", "1024"],
         # n15 with S's bins of one view over the same positions and paths for every light direction:
         # the tables 2.5 (R) to 4 (R_ir) times faster, their noise alike along wi (docs/displacement.md §6).
         "n15-shared": ["--paths", "4", "--angular-resolution", "15", "--pairs", "16000", "--positions", "1024",
                        "--shared-positions"],
         # n15-shared's saving spent on eight times the positions (docs/displacement.md §6).
         "shared8k": ["--paths", "4", "--angular-resolution", "15", "--pairs", "16000", "--positions", "8192",
                      "--shared-positions"]}
# The tables' estimates the tool draws (kTableSampling in prefilter/scaling_factorization.h): tables
# of another are made anew. Until 2026-12-01 the k-th positions of all S bins shared one estimate
# where they met the same coarse cell, which at 32x and 64x they always did: the S bins one sun reads
# moved the image together, by 2.1 points over three seeds for the noise at 64x and by 2.3 over two
# for the woven map at 32x. With each bin its own estimates, 4 paths per position, two seeds: the
# noise at 64x +0.50% and +0.62%, the woven map at 32x -0.70% and -1.01% (docs/displacement.md §9,
# "How far the tables' draw moves the image").
TABLE_SAMPLING = 2


CAMERA = {"position": [-0.55, -1.25, 1.05], "target": [0.5, 0.5, 0], "up": [0, 0, 1], "fov": 34}
SUN = {"type": "sun", "direction": [0.62, -0.38, -0.69], "strength": 3.0}
SKY = {"type": "env", "radiance": [0.25, 0.3, 0.4]}
# lights, --max-depth (-1: the default). "sun" and "sky" are global illumination's two parts, each
# alone with every bounce: an image under "gi" is the sum of the two, so each model's error under "gi"
# is their errors weighted by each light's share of the reference (section 2's split; no gate of its own).
LIGHTING = {"direct": ([SUN], 1), "gi": ([SUN, SKY], -1), "sun": ([SUN], -1), "sky": ([SKY], -1)}
GATED_LIGHTING = ("direct", "gi")  # the issue's two lightings
# Over 4 x 4 tiles toward +y, low: a pixel's footprint grows from 1.7 original cells (of a map of
# 512 per tile) at the bottom row to 43 at the far edge, above which is sky.
LOD_CAMERA = {"position": [2.0, -0.05, 0.22], "target": [2.0, 1.2, 0.0], "up": [0, 0, 1], "fov": 40}
LOD_TILES = [4, 4]
# Which width of a pixel's footprint picks the mipmap's levels (vdb_render's "footprint"), as the report says it.
LOD_FOOTPRINT = {"narrow": "its width across the view", "area": "the square root of its area"}
# Section 5: a glossy base, like the chapter's twill and silk, whose highlights alias when a pixel
# covers many cells; seen as CAMERA sees one tile, scaled to the tiles.
GLOSSY = {"distribution": "ggx", "roughness": 0.15, "specular": 0.6, "diffuse": [0.15, 0.1, 0.05]}
# The ball: bumps over a sphere of 8 tiles of width 1 around the equator (radius 1.27).
BALL = {"map": "bumps", "placement": {"sphere": [0, 0, 0], "tiles": [8, 4]},
        "camera": {"position": [0.8, -4.2, 1.6], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 40}}
BALL_RADIUS = 8 / (2 * math.pi)  # tiles of width 1 around the equator
# A general mesh (surface/mesh_shell.h): the bumps map over a torus
# of 96 x 48 quads by its UVs, 18 tiles around the ring and 7 around the tube, about 1 wide each
# (0.72 on the inner equator, 1.28 on the outer): curvature of both signs, tiles stretched and seams
# both ways. Its map has --torus-cells^2 cells (128: 8.9 M triangles over the mesh at full resolution).
TORUS = {"map": "bumps", "ring": 1 / 0.35, "tube": 0.4 / 0.35, "quads": (96, 48),
         "placement": {"mesh": "torus.obj", "tiles": [18, 7]},
         "camera": {"position": [1.43, -9.14, 5.71], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 40}}
# Each curved base's curvature for --curved-tables: the ball's 1 / radius; the torus's mean curvature
# averaged over its outer, convex half by area, (pi R / r + 4) / (2 (pi R + 2 r)) (0.526; the
# normal curvatures there run from 0 to 1 / r = 0.875, its inner half is a saddle).
BALL["curvature"] = 1 / BALL_RADIUS
TORUS["curvature"] = ((math.pi * TORUS["ring"] / TORUS["tube"] + 4) /
                      (2 * (math.pi * TORUS["ring"] + 2 * TORUS["tube"])))
CURVED = {"ball": BALL, "torus": TORUS}
# Each surface's scale in the chapter (Table 4.3: twill 8x, bump 16x, noise 64x, relief 16x; the
# torus carries the bump map), studied in sections 1-2 besides --factors unless --no-chapter-scales.
CHAPTER_SCALES = {"woven": 8, "ball": 16, "noise": 64, "relief": 16, "torus": 16}
CHAPTER_SCALES_TEXT = ", ".join(f"{surface} {factor}x" for surface, factor in CHAPTER_SCALES.items())


def map_kind(surface):
    return CURVED[surface]["map"] if surface in CURVED else surface


def write_torus(path):
    """TORUS's mesh as an OBJ: vertex (a, b) at u = a / n_u around the ring, v = b / n_v around the
    tube, with its normals; counter-clockwise seen from outside."""
    R, r, (nu, nv) = TORUS["ring"], TORUS["tube"], TORUS["quads"]
    lines, faces = [], []
    for b in range(nv + 1):
        for a in range(nu + 1):
            phi, theta = 2 * math.pi * a / nu, 2 * math.pi * b / nv
            n = (math.cos(theta) * math.cos(phi), math.cos(theta) * math.sin(phi), math.sin(theta))
            lines += [f"v {(R + r * math.cos(theta)) * math.cos(phi):.9f} "
                      f"{(R + r * math.cos(theta)) * math.sin(phi):.9f} {r * math.sin(theta):.9f}",
                      f"vt {a / nu:.9f} {b / nv:.9f}", f"vn {n[0]:.9f} {n[1]:.9f} {n[2]:.9f}"]
    index = lambda a, b: b * (nu + 1) + a + 1
    for b in range(nv):
        for a in range(nu):
            q = [index(a, b), index(a + 1, b), index(a + 1, b + 1), index(a, b + 1)]
            faces.append("f " + " ".join(f"{i}/{i}/{i}" for i in q))
    resumable.write_if_changed(path, "\n".join(lines + faces) + "\n")  # unchanged, it keeps its time (--resume)


run = resumable.run_command


def tool(build, name):
    return pathlib.Path(build) / "bin" / name


def rgb(value):
    return list(value) if isinstance(value, (list, tuple)) else [value] * 3


def same_brdf(written, brdf):
    """The manifest's BRDF (vdb_displacement_prefilter writes colours as triples) against ours."""
    return all(written.get(k) == brdf.get(k) for k in ("distribution", "roughness")) and \
        all(rgb(written.get(k, 0)) == rgb(brdf.get(k, 0)) for k in ("specular", "diffuse"))


def reusable(manifest, report, cells, factor, brdf, rates, stretches="", view_horizon=0.0, base_curvature=0.0,
             relief_radius=0, seed=1, edges="open"):
    """Whether a manifest of an earlier run prefilters this map (its cells) with these settings."""
    if not (manifest.exists() and report.exists()):
        return False
    m = json.loads(manifest.read_text())
    if m.get("settings", {}).get("edges", "open") != edges:
        return False
    if m.get("settings", {}).get("seed", 1) != seed:
        return False
    if abs(m.get("settings", {}).get("base_curvature", 0.0) - base_curvature) > 1e-9:
        return False
    if m.get("settings", {}).get("relief_radius", 0) != relief_radius:
        return False
    if m.get("settings", {}).get("stretches", []) != (stretches.split(",") if stretches else []):
        return False
    if m.get("settings", {}).get("view_horizon_degrees", 0.0) != view_horizon:
        return False
    if m.get("settings", {}).get("table_sampling", 1) != TABLE_SAMPLING:
        return False  # made before the tables' estimates changed (kTableSampling)
    history = m.get("settings", {}).get("history", "")
    shared = "--shared-positions" in RATES[rates]  # n15's flags are a prefix of n15-shared's
    return (m.get("factor") == factor and m.get("cells", [0])[0] * factor == cells and
            same_brdf(m.get("brdf", {}), brdf) and " ".join(RATES[rates]) in history and
            ("--shared-positions" in history) == shared)


def map_cells(args, surface):
    return {"ball": args.ball_cells, "torus": args.torus_cells, "ball_scale": args.ball_scale_cells}.get(surface, args.cells)


def prefilter(args, out, surface, factor, scaling, brdf=None, tag="", seed=1, tiled=None):
    """The manifest of this map at this factor (made unless an earlier run's is reusable) and its report;
    `seed`: vdb_displacement_prefilter's (the NDFs' EM, the tables' positions and paths), other than 1 named in
    the files; `tiled`: whether the images that read them show the map tiled (by default the curved surfaces'
    sections 1-2; sections 4-5 tile every map)."""
    # With --periodic-tables, the tables of the map as a tile among its copies (docs/displacement.md §6,
    # "Tables over a periodic tile"): "tiled", those that tiled images read; "all", every one, the planes'
    # lone tile's too. A plane's periodic tables are named apart from its lone tile's, which sections 1-2 read.
    tiled = surface in CURVED if tiled is None else tiled
    periodic = args.periodic_tables == "all" or (args.periodic_tables == "tiled" and tiled)
    edges = "periodic" if periodic else "open"
    tag += "_periodic" if periodic and surface not in CURVED else ""
    tag += "" if seed == 1 else f"_seed{seed}"
    manifest = out / f"{surface}_{factor}x_{scaling}{tag}.json"
    report = out / f"{surface}_{factor}x_{scaling}{tag}.report.json"
    build, rates = args.build, args.rates
    # The ball's tiles narrow toward its poles: tables also for the tiles squeezed to --ball-stretches.
    stretches = args.ball_stretches if surface == "ball" else ""
    # And on curved bases S up to the view's horizon, which their rims show (docs/displacement.md §6,
    # "The view's horizon").
    # On the planes with --planar-view-horizon (their level-of-detail view grazes them).
    view_horizon = args.curved_view_horizon if surface in CURVED else args.planar_view_horizon
    # With --curved-tables, their tables over a base as convex as theirs (docs/displacement.md §6,
    # "Tables for a curved base").
    curvature = CURVED[surface]["curvature"] if args.curved_tables and surface in CURVED else 0.0
    # On the curved bases the relief term, over at most the coarse map's cells (2 R + 1 of them;
    # docs/displacement.md §6, "The relief term"): past their silhouettes the image sees their cells by
    # their height.
    relief_radius = min(args.relief_radius, (map_cells(args, surface) // factor - 1) // 2) if surface in CURVED else 0
    if not reusable(manifest, report, map_cells(args, surface), factor, brdf or BRDF, rates, stretches, view_horizon,
                    curvature, relief_radius, seed, edges):
        run([tool(build, "vdb_displacement_prefilter"), out / f"{surface}.exr", manifest, "--factor", factor,
             "--scaling", scaling, "--brdf", json.dumps(brdf or BRDF), "--report", report] + RATES[rates] +
            (["--seed", seed] if seed != 1 else []) +
            (["--stretch", stretches] if stretches else []) +
            (["--view-horizon", view_horizon] if view_horizon else []) +
            (["--base-curvature", curvature] if curvature else []) +
            (["--relief-radius", relief_radius] if relief_radius else []) +
            (["--periodic"] if periodic else []))
    return manifest, json.loads(report.read_text())


def height_field(model, surface, manifest):
    placement = CURVED[surface]["placement"] if surface in CURVED else {}
    if model == "reference":
        return {"file": f"{surface}.exr", "brdf": BRDF, **placement}
    if model == "naive":
        return {"file": manifest.name.replace(".json", ".height.exr"), "brdf": BRDF, **placement}
    return {"prefiltered": manifest.name, "scaling": model == "full", **placement}


def render(args, out, name, field, lighting, res, spp=None, seconds=None, seed=1, reuse=None, camera=CAMERA,
           memory=False):
    """vdb_render of one height field; with --resume skipped where an earlier run rendered the same scene
    from the same files (scripts/resumable.py). Returns the image and the seconds it took."""
    lights, depth = LIGHTING[lighting]
    # The same reference for every factor: `reuse` holds the names this run has rendered (an image of
    # an earlier run may be of another map or another size).
    if reuse is not None and name in reuse:
        return out / f"{name}.exr", 0
    if reuse is not None:
        reuse.add(name)
    scene = out / f"{name}.scene.json"
    resumable.write_if_changed(scene, json.dumps({"resolution": res, "seed": seed, "camera": camera, "lights": lights,
                                                  "height_fields": [field]}, indent=1))
    image = out / f"{name}.exr"
    cmd = ["/usr/bin/time", "-v", "-o", out / f"{name}.time.txt"] if memory else []
    renderer = tool(args.build, "vdb_render")
    cmd += [renderer, "--scene", scene, "-o", image, "--preview", out / f"{name}.png",
            "--report", out / f"{name}.render.json"]
    cmd += ["--time", seconds, "--spp", 1 << 20] if seconds else ["--spp", spp]
    if depth > 0:
        cmd += ["--max-depth", depth]
    outputs = [image, out / f"{name}.png", out / f"{name}.render.json"] + ([out / f"{name}.time.txt"] if memory else [])
    inputs = [renderer, *libraries(args.build), scene, *field_inputs(out, field)]
    return image, resumed(args, name, resumable.run_resumable(cmd, outputs, inputs, args.resume))


def libraries(build):
    """The project's shared libraries that its tools load."""
    return sorted(pathlib.Path(build).glob("libvdbappear/lib*.so*"))


def field_inputs(out, field):
    """The files a height field of a scene reads: its map, mesh, and each prefiltered manifest with its
    parts (the files named after it)."""
    names = [field.get("file"), field.get("prefiltered"), field.get("mesh"), *field.get("mipmap", [])]
    files = []
    for name in filter(None, names):
        files += sorted(out.glob(name[:-len(".json")] + ".*")) if name.endswith(".json") else [out / name]
    return files


def resumed(args, name, result):
    """The seconds of a run_resumable() result; a skipped command's name is kept for the report."""
    stdout, record = result
    if stdout is None:
        args.resumed.append(name)
    return record["seconds"]


def make_map(args, kind, cells, path):
    """vdb_make_height_map's map `kind` at cells^2 cells into path (kept with --resume if it made it so)."""
    cmd = [tool(args.build, "vdb_make_height_map"), kind, "--cells", cells, "-o", path]
    resumed(args, pathlib.Path(path).name, resumable.run_resumable(cmd, [path], [cmd[0], *libraries(args.build)],
                                                                   args.resume))


def compare(build, reference, test, error_map=None, mask=None):
    cmd = [tool(build, "vdb_image_compare"), reference, test, "--report", "-", "--range", "0.5"]
    if error_map:
        cmd += ["--error-map", error_map, "--side-by-side", str(error_map).replace("error", "sbs")]
    if mask:
        cmd += ["--mask", mask]
    return json.loads(run(cmd))


def mean_error_standard_error(out, test, reference):
    """One standard error of the relative error of `test`'s image mean against `reference`'s, from
    the renders' own noise (each render.json's mean pixel variance, the variance of a pixel's mean):
    the image mean's variance is that over the pixel count, and the ratio's by the delta method.
    Channels of one pixel are counted as one (their paths are the same), which errs high."""
    def mean_and_variance(name):
        stats = json.loads((out / f"{name}.render.json").read_text())
        pixels = stats["resolution"][0] * stats["resolution"][1]
        return stats["mean_pixel_value"], stats["mean_pixel_variance"] / pixels
    m_t, v_t = mean_and_variance(test)
    m_r, v_r = mean_and_variance(reference)
    if m_t <= 0 or m_r <= 0:
        return None
    return m_t / m_r * math.sqrt(v_t / m_t ** 2 + v_r / m_r ** 2)


def region_masks(args, out, surface, lighting):
    """The masks of a curved surface's regions: the ball's by sphere_regions.py, the torus's by
    torus_regions.py; [(name, path, pixel count)]. The regions follow SUN, which every lighting but "sky"
    holds (under "sky" alone they still split the surface by where the sun would be)."""
    width, height = [int(v) for v in args.res.split("x")]
    camera, tag = CURVED[surface]["camera"], f"{surface}_{lighting}"
    if surface == "ball":
        return sphere_regions.region_masks(out, tag, camera, BALL["placement"]["sphere"], BALL_RADIUS,
                                           SUN["direction"], width, height)
    return torus_regions.region_masks(out, tag, camera, [0, 0, 0], TORUS["ring"], TORUS["tube"], SUN["direction"],
                                      width, height)


def curved_regions(args, out, surface, lighting, reference, images, reference_mean):
    """A curved surface's error by region of its base surface (region_masks): per region its pixels,
    its share of the reference's light, and per model the relative error there (None where the
    reference is black) and its part of the image mean's relative error (the parts add up to it)."""
    width, height = [int(v) for v in args.res.split("x")]
    whole = reference_mean * width * height
    regions = []
    for name, mask, pixels in region_masks(args, out, surface, lighting):
        if pixels == 0 or whole <= 0:
            continue
        region = {"region": name, "pixels": pixels}
        for model, image in images.items():
            c = compare(args.build, reference, image, mask=mask)
            region[model] = {"error": c["mean_relative_error"] if c["mean_reference"] > 0 else None,
                             "part": (c["mean_test"] - c["mean_reference"]) * pixels / whole}
        region["share"] = c["mean_reference"] * pixels / whole  # the reference's, the same in every compare
        regions.append(region)
    return regions


@functools.lru_cache(maxsize=None)
def sun_bins(n, width, height):
    """The S bins (N = n) that the planes' images read under the sun, and their weights
    (table_draw.bins_read): the same for every plane, so traced once."""
    return table_draw.bins_read(CAMERA, SUN["direction"], n, width, height)


def tables_spread(manifest, prefilter_report, res):
    """How far S's draw moves a planar image's mean under the sun (scripts/table_draw.py), every bin
    of the table's median relative error; None where its bins do not err independently (shared
    positions) or report no error. S's N is the manifest's own."""
    q = prefilter_report["scaling"]["S"].get("relative_standard_error")
    if not q or prefilter_report["settings"].get("shared_positions"):
        return None
    n = json.loads(manifest.read_text())["angular_resolution"]
    return table_draw.image_spread(q["median"], sun_bins(n, *res))


def study_factors(args, surface):
    """Sections 1-2's factors for this surface: --factors and, unless --no-chapter-scales, its scale in
    the chapter (CHAPTER_SCALES) where its map's cells allow it."""
    factors = {int(f) for f in args.factors.split(",")}
    chapter = CHAPTER_SCALES.get(surface)
    if not args.no_chapter_scales and chapter and map_cells(args, surface) % chapter == 0:
        factors.add(chapter)
    return sorted(factors)


def report_tables(args, timing_rows, label, factor, scaling, manifest, prefilter_report):
    """The report's row of a model's precomputation (Table 4.3-4.4), once per set of tables: sections 4-5
    add one only for tables of their own (periodic ones, or with --no-study)."""
    if manifest.name in args.reported_tables:
        return
    args.reported_tables.add(manifest.name)
    timing_rows.append({"surface": label, "factor": factor, "scaling": scaling, "tables": manifest.name,
                        "seconds": prefilter_report["settings"]["seconds"], "bytes": prefilter_report["bytes"],
                        "ranges": prefilter_report["scaling"]})


def study(args, out, surface, factor, rows, timing_rows):
    res = [int(v) for v in args.res.split("x")]
    camera = CURVED[surface]["camera"] if surface in CURVED else CAMERA
    for lighting in args.lighting.split(","):
        scaling = scaling_for(lighting)
        manifest, prefilter_report = prefilter(args, out, surface, factor, scaling)
        report_tables(args, timing_rows, surface, factor, scaling, manifest, prefilter_report)
        tag = f"{surface}_{factor}x_{lighting}"
        reference, _ = render(args, out, f"{surface}_{lighting}_reference",
                              height_field("reference", surface, manifest), lighting, res, spp=args.spp_ref,
                              reuse=args.rendered, camera=camera)
        row = {"surface": surface, "factor": factor, "lighting": lighting}
        images = {}
        for model in ("naive", "multi-lobe", "full"):
            images[model], _ = render(args, out, f"{tag}_{model}", height_field(model, surface, manifest), lighting,
                                      res, spp=args.spp, camera=camera)
            c = compare(args.build, reference, images[model], out / f"{tag}_{model}_error.png")
            row[model] = c["mean_relative_error"]
            row.setdefault("standard_error", {})[model] = mean_error_standard_error(
                out, f"{tag}_{model}", f"{surface}_{lighting}_reference")
        if len(args.seeds) > 1:
            row["full_over_seeds"] = full_over_seeds(args, out, surface, factor, lighting, reference, row["full"], camera)
        if surface in CURVED:
            row["regions"] = curved_regions(args, out, surface, lighting, reference, images, c["mean_reference"])
        if lighting == "direct" and surface not in CURVED:
            row["tables_spread"] = tables_spread(manifest, prefilter_report, tuple(res))
        row["reference_mean"] = c["mean_reference"]
        row["passed"] = abs(row["full"]) <= gate_bar(row["naive"]) if lighting in GATED_LIGHTING else None
        if lighting == "gi" and args.equal_time > 0:
            # Another seed for the reference of the noise measurement, so that noise does not cancel.
            converged, _ = render(args, out, f"{surface}_gi_converged", height_field("reference", surface, manifest),
                                  lighting, res, spp=args.spp_ref, seed=7, reuse=args.rendered, camera=camera)
            for model in ("reference", "full"):
                image, _ = render(args, out, f"{tag}_{model}_equal_time", height_field(model, surface, manifest),
                                  lighting, res, seconds=args.equal_time, camera=camera)
                stats = json.loads((out / f"{tag}_{model}_equal_time.render.json").read_text())
                row[f"equal_time_{model}"] = {"rmse": compare(args.build, converged, image)["rmse"],
                                              "spp": stats.get("spp"), "seconds": stats.get("seconds")}
        rows.append(row)
        print(f"{tag}: mean error naive {row['naive']:+.2%}, multi-lobe {row['multi-lobe']:+.2%}, "
              f"full {row['full']:+.2%} ({gate_text(row['passed']).upper()})", flush=True)


def scaling_for(lighting):
    """The scaling function a lighting's full model carries: R (Eq. 4.12) for one bounce, R_ir (Eq. 4.20) for all."""
    return "shadowing" if lighting == "direct" else "interreflection"


def gate_bar(naive):
    """The issue's gate on the full model's relative error of the image mean: at most 3% and at most a
    third of naive's."""
    return min(0.03, abs(naive) / 3)


def full_over_seeds(args, out, surface, factor, lighting, reference, first_error, camera):
    """The full model's error with its tables made at each of --table-seeds (the first is the row's own):
    how far the tables' draw moves the image mean, measured (seed_summary)."""
    res = [int(v) for v in args.res.split("x")]
    errors = [first_error]
    for seed in args.seeds[1:]:
        manifest, _ = prefilter(args, out, surface, factor, scaling_for(lighting), seed=seed)
        name = f"{surface}_{factor}x_{lighting}_full_seed{seed}"
        image, _ = render(args, out, name, height_field("full", surface, manifest), lighting, res, spp=args.spp,
                          camera=camera)
        errors.append(compare(args.build, reference, image)["mean_relative_error"])
    return {"seeds": args.seeds, **seed_summary(errors)}


def seed_summary(errors):
    """The errors of one model over its tables' seeds: each, their mean, their sample standard deviation
    (the tables' draw with the renders' noise) and the mean's standard error (that over sqrt(n))."""
    deviation = statistics.stdev(errors) if len(errors) > 1 else float("nan")
    return {"errors": errors, "mean": statistics.mean(errors), "deviation": deviation,
            "standard_error": deviation / math.sqrt(len(errors))}


def gate_text(passed):
    return "no gate" if passed is None else "pass" if passed else "fail"


def light_split(rows):
    """Section 2's split of global illumination: for each surface and factor rendered under "gi", "sun" and
    "sky", each light's share of the reference's mean and each model's error under it; the errors
    weighted by the shares add up to the error under "gi" within the renders' noise (the images add)."""
    by_key = {(r["surface"], r["factor"], r["lighting"]): r for r in rows}
    splits = []
    for gi in (r for r in rows if r["lighting"] == "gi"):
        sun, sky = (by_key.get((gi["surface"], gi["factor"], light)) for light in ("sun", "sky"))
        if sun is None or sky is None:
            continue
        share = sun["reference_mean"] / (sun["reference_mean"] + sky["reference_mean"])
        split = {"surface": gi["surface"], "factor": gi["factor"], "sun_share": share}
        for model in ("naive", "multi-lobe", "full"):
            split[model] = {"sun": sun[model], "sky": sky[model], "gi": gi[model],
                            "sum": share * sun[model] + (1 - share) * sky[model]}
        splits.append(split)
    return splits


def peak_memory_mb(out, name):
    for line in (out / f"{name}.time.txt").read_text().splitlines():
        if "Maximum resident set size" in line:
            return int(line.split(":")[-1]) / 1024
    return float("nan")


def level_of_detail(args, out, surface, lod_rows, timing_rows):
    """Section 4: the mipmap against the original at equal render time, over a grazing tiled view."""
    res = [int(v) for v in args.res.split("x")]
    # The R_ir models of sections 1-2 (made here when --no-study left them out; reused otherwise), or with
    # --periodic-tables tiled their own over a periodic tile: this view shows the map tiled.
    levels, manifest = [], None
    for factor in [int(f) for f in args.factors.split(",")]:
        manifest, prefilter_report = prefilter(args, out, surface, factor, "interreflection", tiled=True)
        report_tables(args, timing_rows, f"{surface} (level of detail)", factor, "interreflection", manifest,
                      prefilter_report)
        levels.append(manifest.name)
    fields = {"original": {"file": f"{surface}.exr", "brdf": BRDF, "tiles": LOD_TILES},
              "mipmap": {"file": f"{surface}.exr", "mipmap": levels, "tiles": LOD_TILES, "footprint": args.lod_footprint},
              "models": {"mipmap": levels, "tiles": LOD_TILES, "footprint": args.lod_footprint}}
    reference, _ = render(args, out, f"{surface}_lod_reference", fields["original"], "gi", res,
                          spp=args.lod_spp_ref, seed=7, reuse=args.rendered, camera=LOD_CAMERA)
    n = json.loads(manifest.read_text())["angular_resolution"]  # S's N, the same at every level (one --rates)
    masks = plane_view_bands.region_masks(out, f"{surface}_lod", LOD_CAMERA, LOD_TILES, n, *res)
    for spp in [int(v) for v in args.lod_spp.split(",")]:
        seconds, results = equal_time(args, out, f"{surface}_lod", fields, reference, spp, LOD_CAMERA)
        row = {"surface": surface, "spp": spp, "seconds": seconds, **results,
               "bands": lod_bands(args, out, f"{surface}_lod", fields, spp, reference, masks)}
        lod_rows.append(row)
        print(f"{surface} level of detail, {row['seconds']:.2f} s: RMSE original {row['original']['rmse']:.4f},"
              f" mipmap {row['mipmap']['rmse']:.4f}, models alone {row['models']['rmse']:.4f}", flush=True)


def lod_bands(args, out, tag, fields, spp, reference, masks):
    """The level-of-detail view's error by how steeply it sees the plane (plane_view_bands.py; the last band
    beyond S's outermost bins): per band its pixels, its share of the reference's light on the tiles and
    each field's mean error there."""
    bands = []
    for name, mask, pixels in masks[:-1]:  # the last: off the tiles
        if pixels == 0:
            continue
        band = {"band": name, "pixels": pixels}
        for model in fields:
            c = compare(args.build, reference, out / f"{tag}_{model}_{spp}.exr", mask=mask)
            band[model] = c["mean_relative_error"]
        band["light"] = c["mean_reference"] * pixels  # the reference's, the same in every compare
        bands.append(band)
    tiles_light = sum(b["light"] for b in bands)
    for b in bands:
        b["share"] = b.pop("light") / tiles_light if tiles_light > 0 else float("nan")
    return bands


def equal_time(args, out, tag, fields, reference, spp, camera, res=None):
    """The first field ("original") at spp samples per pixel, every other for the time it took, under
    global illumination: the seconds, and per field its RMSE, mean error, spp and peak memory against
    the reference, and its noise: the RMS over pixels of the standard error of a pixel's mean (from
    vdb_render's report, the mean over pixels and channels of that variance)."""
    res = res or [int(v) for v in args.res.split("x")]
    seconds, results = None, {}
    for model, field in fields.items():
        name = f"{tag}_{model}_{spp}"
        timing = {"spp": spp} if seconds is None else {"seconds": seconds}
        render(args, out, name, field, "gi", res, camera=camera, memory=True, **timing)
        stats = json.loads((out / f"{name}.render.json").read_text())
        c = compare(args.build, reference, out / f"{name}.exr", out / f"{name}_error.png")
        results[model] = {"rmse": c["rmse"], "mean": c["mean_relative_error"], "spp": stats.get("spp"),
                          "peak_mb": peak_memory_mb(out, name), "noise": math.sqrt(stats["mean_pixel_variance"])}
        if seconds is None:
            seconds = stats["seconds"]
    return seconds, results


def scaled_camera(tiles):
    return {"position": [tiles * v for v in CAMERA["position"]], "target": [tiles * v for v in CAMERA["target"]],
            "up": CAMERA["up"], "fov": CAMERA["fov"]}


def equal_time_at_scale(args, out, surface, tag, placement, camera, res, scale_rows, timing_rows, label=None):
    """Section 5 for one map (out/{surface}.exr) placed by `placement`: the glossy base, its R_ir models at
    --factors, each rendered for the time the original takes at --scale-spp, against the original at
    --scale-spp-ref (another seed); images named after `tag`, rows after `label` (the map's name)."""
    fields = {"original": {"file": f"{surface}.exr", "brdf": GLOSSY, **placement}}
    for factor in [int(f) for f in args.factors.split(",")]:
        manifest, prefilter_report = prefilter(args, out, surface, factor, "interreflection", brdf=GLOSSY,
                                               tag="_glossy", tiled=True)
        report_tables(args, timing_rows, f"{surface} (glossy)", factor, "interreflection", manifest, prefilter_report)
        fields[f"{factor}x"] = {"prefiltered": manifest.name, "scaling": True, **placement}
    reference, _ = render(args, out, f"{tag}_reference", fields["original"], "gi", res,
                          spp=args.scale_spp_ref, seed=7, reuse=args.rendered, camera=camera)
    for spp in [int(v) for v in args.scale_spp.split(",")]:
        seconds, results = equal_time(args, out, tag, fields, reference, spp, camera, res)
        row = {"surface": label or surface, "tag": tag, "spp": spp, "seconds": seconds, "original": results.pop("original"),
               "models": results}
        scale_rows.append(row)
        print(f"{row['surface']} at scale, {row['seconds']:.2f} s: RMSE original {row['original']['rmse']:.4f}, " +
              ", ".join(f"{m} {r['rmse']:.4f}" for m, r in row["models"].items()), flush=True)


def chapter_scale(args, out, surface, scale_rows, timing_rows):
    """Section 5: equal time with a glossy base over many tiles seen from afar (Table 4.5's setting)."""
    equal_time_at_scale(args, out, surface, f"{surface}_scale", {"tiles": [args.scale_tiles, args.scale_tiles]},
                        scaled_camera(args.scale_tiles), [int(v) for v in args.res.split("x")], scale_rows,
                        timing_rows)


def ball_cells_per_pixel(args, tiles=8):
    """Original cells across a pixel where the ball of `tiles` tiles around its equator faces the camera
    (tiles of width 1 there; the sphere and the camera scaled by tiles / 8; the camera's fov is
    vertical)."""
    camera, height = BALL["camera"], int(args.ball_scale_res.split("x")[1])
    distance = math.dist(camera["position"], BALL["placement"]["sphere"]) - BALL_RADIUS
    return 2 * math.tan(math.radians(camera["fov"] / 2)) * distance / height * args.ball_scale_cells * tiles / 8


def ball_scale_tiles(args):
    return [int(t) for t in args.ball_scale_tiles.split(",")]


def ball_at_scale(args, out, scale_rows, timing_rows):
    """Section 5 on the ball: the bumps map at --ball-scale-cells^2 over T x T/2 tiles for each T of
    --ball-scale-tiles, the ball of sections 1-2 and its view scaled by T / 8 (the same image at
    T = 8), seen at --ball-scale-res. A band of tiles is one tile's triangles and turned copies of it."""
    make_map(args, "bumps", args.ball_scale_cells, out / "ball_scale.exr")
    for k, tiles in enumerate(ball_scale_tiles(args)):
        grow = tiles / 8
        camera = {**BALL["camera"], "position": [grow * v for v in BALL["camera"]["position"]]}
        placement = {**BALL["placement"], "tiles": [tiles, tiles // 2]}
        equal_time_at_scale(args, out, "ball_scale", f"ball_scale_{tiles}", placement, camera,
                            [int(v) for v in args.ball_scale_res.split("x")], scale_rows,
                            timing_rows if k == 0 else [],  # one map, its tables made (and reported) once
                            label=f"ball, {tiles} x {tiles // 2} tiles")


def with_standard_error(row, model):
    """A row's mean error of `model` with its renders' standard error: "+0.41% ± 0.04%"."""
    se = row.get("standard_error", {}).get(model)
    return f"{row[model]:+.2%}" + (f" ± {se:.2%}" if se is not None else "")


def table_error(ranges):
    """S's bins' relative standard errors from a prefilter report's ranges: "median / 90% / 99%"."""
    q = ranges["S"].get("relative_standard_error")
    return "n/a" if not q else f"{q['median']:.1%} / {q['p90']:.1%} / {q['p99']:.1%}"


def report_header(args, seconds):
    """The report's title, the command line that reproduces it, and the tables' sampling rates."""
    command = (f"`scripts/displacement_experiment.py --cells {args.cells} --factors {args.factors} --rates {args.rates}"
               f" --lighting {args.lighting} --surfaces {args.surfaces}" +
               (" --no-chapter-scales" if args.no_chapter_scales else "") +
               (f" --table-seeds {args.table_seeds}" if len(args.seeds) > 1 else "") +
               (f" --periodic-tables {args.periodic_tables}" if args.periodic_tables != "none" else "") +
               (f" --planar-view-horizon {args.planar_view_horizon:g}" if args.planar_view_horizon else "") +
               (f" --lod-footprint {args.lod_footprint}" if args.lod_footprint != "narrow" else "") +
               f" --spp-ref {args.spp_ref} --spp {args.spp} --equal-time {args.equal_time} --res {args.res}`,")
    resumed = (f" With --resume, {len(args.resumed)} maps and renders were an earlier run's, of the same commands from"
               " the same files, and were not run again (report.json's \"resumed\"); the tables an earlier run made"
               " with the same settings are reused always." if args.resumed else "")
    rates = ("the chapter's (§4.7.1: 2500 paths per estimate, 5000 pairs per T bin, 16 positions per S bin, N = 15, "
             "M = 4)." if args.rates == "chapter" else
             f"{args.rates} (" + " ".join(RATES[args.rates]) + "; M = 4), not the chapter's.")
    periodic = {"none": "", "tiled": " The tables of the images that show the map tiled over a periodic tile"
                                     " (--periodic): the ball's and the torus's, and sections 4-5's; the planes' of"
                                     " sections 1-2 over the map alone.",
                "all": " Every table over a periodic tile (--periodic), the planes' lone tile's too."}[args.periodic_tables]
    return ["# Displacement-map prefiltering (issue 23): measured", "",
            command + f" {seconds / 60:.1f} min in all on this machine." + resumed, "",
            "Sampling rates: " + rates + periodic, ""]


def report_mean_intensity(rows):
    """Sections 1-2: each model's error of the image mean, and the issue's gate."""
    lines = ["## Mean intensity against the full-resolution reference", "",
             "Relative error of the image mean; the gate: |full| <= 3% and <= |naive| / 3. \"The chapter's\": the "
             f"surface's scale in Table 4.3 ({CHAPTER_SCALES_TEXT}; the woven map as the twill, the ball and the "
             "torus as the bump). After each error, ± one standard error from the renders' own noise (the model's "
             "and the reference's); the tables' own draw adds to it (the precomputation table's \"S's bins' "
             "error\"). \"S's draw\": how far that draw moves the full model's image mean, one standard "
             "deviation, on the planes under the sun, where the image reads few of S's bins "
             "(scripts/table_draw.py, each bin of the table's median error; docs/displacement.md §9).", "",
             "| surface | factor | light | naive | multi-lobe | full | S's draw | gate |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        chapter = " (the chapter's)" if CHAPTER_SCALES.get(r["surface"]) == r["factor"] else ""
        errors = " | ".join(with_standard_error(r, m) for m in ("naive", "multi-lobe", "full"))
        draw = r.get("tables_spread")
        lines.append(f"| {r['surface']} | {r['factor']}x{chapter} | {r['lighting']} | {errors} |"
                     f" {'n/a' if draw is None else f'± {draw:.2%}'} | {gate_text(r['passed'])} |")
    return lines


def report_seeds(args, rows):
    """The full model over its tables' seeds (--table-seeds), beside the gate's bar."""
    seeded = [r for r in rows if "full_over_seeds" in r]
    if not seeded:
        return []
    lines = ["", "## The full model over its tables' seeds", "",
             f"The full model with its tables made at each of `--table-seeds {args.table_seeds}` (the first is the "
             "table above's), each rendered at --spp against the same reference: the spread is the tables' draw "
             "with the renders' noise. The gate above judges the first seed's tables alone; \"mean within the "
             "bar\" says whether the mean over the seeds lies within the gate's bar (the smaller of naive / 3 and "
             "3%), for information: it is not the issue's gate.", "",
             "| surface | factor | light | naive | bar | full, each seed | mean ± s.e. | std. dev. |"
             " mean within the bar |", "|---|---|---|---|---|---|---|---|---|"]
    for r in seeded:
        f = r["full_over_seeds"]
        bar = gate_bar(r["naive"])
        lines.append(f"| {r['surface']} | {r['factor']}x | {r['lighting']} | {r['naive']:+.2%} | {bar:.2%} | " +
                     ", ".join(f"{e:+.2%}" for e in f["errors"]) +
                     f" | {f['mean']:+.2%} ± {f['standard_error']:.2%} | {f['deviation']:.2%} | "
                     f"{'yes' if abs(f['mean']) <= bar else 'no'} |")
    return lines


def report_light_split(splits):
    """Section 2's split of global illumination into the sun's and the sky's parts."""
    if not splits:
        return []
    lines = ["", "## Global illumination by light", "",
             "The sun and the sky each alone with every bounce (`--lighting sun,sky`): an image under both is "
             "the sum of the two, so a model's error under both is its error under each weighted by that "
             "light's share of the reference (\"sum\"; it differs from the \"gi\" column by the renders' noise "
             "alone). Where naive's error under the sun and under the sky have opposite signs they cancel, "
             "and a small error under both lights does not mean naive keeps the look.", "",
             "| surface | factor | sun's share | model | under the sun | under the sky | sum | under both (gi) |",
             "|---|---|---|---|---|---|---|---|"]
    for t in splits:
        for model in ("naive", "multi-lobe", "full"):
            e = t[model]
            lines.append(f"| {t['surface']} | {t['factor']}x | {t['sun_share']:.1%} | {model} | {e['sun']:+.2%} |"
                         f" {e['sky']:+.2%} | {e['sum']:+.2%} | {e['gi']:+.2%} |")
    return lines


def report_curved_regions(rows):
    """The ball's and the torus's error by where their pixels meet the base surface."""
    curved_rows = [r for r in rows if "regions" in r]
    if not curved_rows:
        return []
    lines = ["", "## The curved surfaces' error by region", "",
             "Pixels by where their camera ray meets the base surface (the ball's sphere: "
             "scripts/sphere_regions.py; the torus: scripts/torus_regions.py, its outer half convex, its inner "
             "half a saddle): by the cosine between its normal there and the sun, in shadow, or past its "
             "silhouette (the bumps' rim). Per region: its share of the reference's light; per model the relative "
             "error of the region's mean, and in parentheses its part of the image mean's relative error (the "
             "parts add up to the table above).", "",
             "| surface | factor | light | region | pixels | share | naive | multi-lobe | full |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in curved_rows:
        for g in r["regions"]:
            lines.append(f"| {r['surface']} | {r['factor']}x | {r['lighting']} | {g['region']} | {g['pixels']} | "
                         f"{g['share']:.1%} | " +
                         " | ".join(("n/a" if g[m]["error"] is None else f"{g[m]['error']:+.1%}") +
                                    f" ({g[m]['part']:+.2%})" for m in ("naive", "multi-lobe", "full"))
                         + " |")
    return lines


def report_equal_time(args, rows):
    """Section 3: the original against the full model at equal render time."""
    lines = ["", "## Equal time (global illumination)", "",
             f"RMSE against a reference of {args.spp_ref} spp (another seed), each model rendered for "
             f"{args.equal_time} s.", "", "| surface | factor | original RMSE (spp) | full model RMSE (spp) | lower |",
             "|---|---|---|---|---|"]
    for r in rows:
        if "equal_time_full" in r:
            o, f = r["equal_time_reference"], r["equal_time_full"]
            lines.append(f"| {r['surface']} | {r['factor']}x | {o['rmse']:.4g} ({o['spp']}) | {f['rmse']:.4g} ({f['spp']}) |"
                         f" {'full' if f['rmse'] < o['rmse'] else 'original'} |")
    return lines


def report_level_of_detail(args, lod_rows):
    """Section 4: the mipmaps against the original at equal time, and their error by the view's angle."""
    if not lod_rows:
        return []
    lines = ["", "## Level of detail (§4.7.2): equal time over a grazing view of 4 x 4 tiles", "",
             f"Global illumination; a pixel's footprint is {1.7 * args.cells / 512:.1f} to {43 * args.cells / 512:.0f} "
             f"original cells wide by the square root of its area ({2.1 * args.cells / 1024:.1f} to "
             f"{20 * args.cells / 1024:.0f} across the view); RMSE and mean relative error "
             f"against the original at {args.lod_spp_ref} spp (another seed). `mipmap`: the original and the R_ir "
             f"models at {args.factors}x as levels; `models`: those models alone; each path on the level its pixel's "
             f"footprint picks, by {LOD_FOOTPRINT[args.lod_footprint]}. Noise: the RMS over pixels of the standard "
             "error of a pixel's mean, from each render's own samples, which leaves the models' bias out (the "
             "chapter's Fig. 4.12 compares noise). Peak memory of vdb_render (/usr/bin/time -v).", "",
             "| surface | seconds | original RMSE (spp) | mipmap RMSE (spp) | models RMSE (spp) | mean error: original,"
             " mipmap, models | noise: original, mipmap, models | peak MB: original, mipmap, models |",
             "|---|---|---|---|---|---|---|---|"]
    for r in lod_rows:
        o, m, n = r["original"], r["mipmap"], r["models"]
        lines.append(f"| {r['surface']} | {r['seconds']:.2f} | {o['rmse']:.4f} ({o['spp']}) | {m['rmse']:.4f} ({m['spp']}) |"
                     f" {n['rmse']:.4f} ({n['spp']}) | {o['mean']:+.2%}, {m['mean']:+.2%}, {n['mean']:+.2%} |"
                     " " + ", ".join(f"{v['noise']:.4f}" for v in (o, m, n)) + " |"
                     f" {o['peak_mb']:.0f}, {m['peak_mb']:.0f}, {n['peak_mb']:.0f} |")
    banded = [r for r in lod_rows if "bands" in r]
    if not banded:
        return lines
    lines += ["", "The mean error by how steeply the view meets the plane (theta_o from its normal; "
              "scripts/plane_view_bands.py); the far band reads S beyond its outermost bins (clamped"
              f"{'' if not args.planar_view_horizon else f', or here its horizon nodes at {args.planar_view_horizon:g} degrees'}):", "",
              "| surface | spp | band | pixels | share of the tiles' light | original | mipmap | models |",
              "|---|---|---|---|---|---|---|---|"]
    for r in banded:
        for b in r["bands"]:
            lines.append(f"| {r['surface']} | {r['spp']} | {b['band']} | {b['pixels']} | {b['share']:.1%} |"
                         f" {b['original']:+.2%} | {b['mipmap']:+.2%} | {b['models']:+.2%} |")
    return lines


def report_chapter_scale(args, scale_rows):
    """Section 5: equal time where the chapter measures it, a pixel over many original cells."""
    if not scale_rows:
        return []
    models = list(scale_rows[0]["models"])
    lines = ["", f"## Equal time at the chapter's scale (Table 4.5): a glossy base over {args.scale_tiles} x "
             f"{args.scale_tiles} tiles", "",
             f"Global illumination; base BRDF {json.dumps(GLOSSY)}; the view of sections 1-3 scaled to the tiles, "
             f"so that a pixel covers about {args.cells * args.scale_tiles / res_width(args):.0f} original cells "
             f"across; each R_ir model rendered for the original's time; RMSE and mean relative error against "
             f"the original at {args.scale_spp_ref} spp (another seed); peak memory of vdb_render. The ball "
             f"(if measured): the same base over its bumps map at {args.ball_scale_cells}^2 cells, T x T/2 tiles "
             f"with the sphere and the view of sections 1-2 scaled by T / 8, seen at {args.ball_scale_res} "
             f"pixels: about " + ", ".join(f"{ball_cells_per_pixel(args, t):.0f} (T = {t})" for t in
                                           ball_scale_tiles(args)) +
             " original cells across a pixel where it faces the camera.", "",
             "| surface | seconds | original RMSE (spp) | " + " | ".join(f"{m} RMSE (spp)" for m in models) +
             " | mean error: original, " + ", ".join(models) + " | peak MB: original, " + ", ".join(models) +
             " | lowest |", "|---" * (6 + len(models)) + "|"]
    for r in scale_rows:
        o, ms = r["original"], r["models"]
        best = min([("original", o["rmse"])] + [(m, v["rmse"]) for m, v in ms.items()], key=lambda p: p[1])[0]
        lines.append(f"| {r['surface']} | {r['seconds']:.2f} | {o['rmse']:.4f} ({o['spp']}) | " +
                     " | ".join(f"{v['rmse']:.4f} ({v['spp']})" for v in ms.values()) +
                     f" | {o['mean']:+.2%}, " + ", ".join(f"{v['mean']:+.2%}" for v in ms.values()) +
                     f" | {o['peak_mb']:.0f}, " + ", ".join(f"{v['peak_mb']:.0f}" for v in ms.values()) + f" | {best} |")
    return lines


def report_precomputation(timing_rows):
    """Tables 4.3-4.4: each set of tables' seconds by step and its parts' bytes."""
    lines = ["", "## Precomputation and storage (Tables 4.3-4.4)", "",
             "Seconds of each step on this machine's cores (the chapter: 22-36 minutes per model); bytes as "
             "32-bit floats.", "",
             "\"Stretched T S\": the tables of the tiles of `--ball-stretches` (docs/displacement.md §6), made "
             "within \"scaling s\". \"S's bins' error\": the relative standard error of S's bins' estimates, "
             "median / 90th / 99th percentile over the bins (docs/displacement.md §6, \"The tables' own error\").", "",
             "| surface | factor | scaling | h_low s | NDFs s | scaling s | original bytes | h_low | SVNDF | T | S | "
             "B (relief term) | stretched T S B | S range | S's bins' error |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for t in timing_rows:
        s, b, rng = t["seconds"], t["bytes"], t["ranges"]["S"]
        lines.append(f"| {t['surface']} | {t['factor']}x | {t['scaling']} | {s['height']:.2f} | {s['ndfs']:.1f} |"
                     f" {s['scaling']:.1f} | {b['original_height']} | {b['height']} | {b['svndf']} | {b['T']} | {b['S']} |"
                     f" {b.get('B', 0)} |"
                     f" {b.get('stretched_tables', 0)} | {rng['min']:.2f}-{rng['max']:.2f} | {table_error(t['ranges'])} |")
    return lines


def report_images(rows, lod_rows, scale_rows):
    """Links to every side-by-side image of the run."""
    lines = ["", "## Images", "", "Each `*_sbs.png`: reference | model | signed relative error (red brighter, blue "
             "darker, saturated at 50%)."]
    for r in rows:
        tag = f"{r['surface']}_{r['factor']}x_{r['lighting']}"
        lines.append(f"- {tag}: " + ", ".join(f"[{m}]({tag}_{m}_sbs.png)" for m in ("naive", "multi-lobe", "full")))
    for r in lod_rows:
        tag = f"{r['surface']}_lod"
        lines.append(f"- {tag}, {r['spp']} spp of the original: " +
                     ", ".join(f"[{m}]({tag}_{m}_{r['spp']}_sbs.png)" for m in ("original", "mipmap", "models")))
    for r in scale_rows:
        tag = r["tag"]
        lines.append(f"- {tag}, {r['spp']} spp of the original: " +
                     ", ".join(f"[{m}]({tag}_{m}_{r['spp']}_sbs.png)" for m in ["original"] + list(r["models"])))
    return lines


def write_report(args, out, rows, timing_rows, lod_rows, seconds, scale_rows=()):
    """report.md, section by section, and report.json with every measured figure."""
    splits = light_split(rows)
    lines = (report_header(args, seconds) + report_mean_intensity(rows) + report_seeds(args, rows) +
             report_light_split(splits) + report_curved_regions(rows) + report_equal_time(args, rows) +
             report_level_of_detail(args, lod_rows) + report_chapter_scale(args, scale_rows) +
             report_precomputation(timing_rows) + report_images(rows, lod_rows, scale_rows))
    (out / "report.md").write_text("\n".join(lines) + "\n")
    (out / "report.json").write_text(json.dumps({"rows": rows, "light_split": splits, "precomputation": timing_rows, "level_of_detail": lod_rows,
                                                 "chapter_scale": list(scale_rows), "resumed": args.resumed}, indent=1))


def res_width(args):
    return int(args.res.split("x")[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="displacement-out")
    parser.add_argument("--cells", type=int, default=1024)
    parser.add_argument("--factors", default="8,32")
    parser.add_argument("--surfaces", default="woven,noise,relief,ball,torus",
                        help="of woven, noise, relief, ball (bumps over a sphere) and torus (bumps over a mesh)")
    parser.add_argument("--rates", choices=sorted(RATES), default="n15",
                        help="n15 (the default since 2026-11-28: every planar model within 0.9%%, sections 1-2 in "
                             "about 96 minutes on 2 cores), quick (minutes), spread, or the chapter's")
    parser.add_argument("--lighting", default="direct,gi",
                        help="of sections 1-3: direct (R) and/or gi (R_ir); sun and sky: gi's two lights each alone "
                             "(R_ir, no gate; the report splits gi's error by light when gi, sun and sky are all given)")
    parser.add_argument("--spp-ref", type=int, default=1024)
    parser.add_argument("--spp", type=int, default=128)
    parser.add_argument("--equal-time", type=float, default=10)
    parser.add_argument("--res", default="192x144")
    parser.add_argument("--lod-spp", default="16,64,256", help="section 4's budgets; empty: no section 4")
    parser.add_argument("--lod-spp-ref", type=int, default=2048)
    parser.add_argument("--ball-cells", type=int, default=1024,
                        help="of the ball's map (the issue's 1K; 256: §9's earlier ball, whose factors cover more of a bump)")
    parser.add_argument("--ball-stretches", default="0.75,0.5,0.3",
                        help="the ball's tables also for its tiles squeezed east-west to these widths (its cosines of "
                             "latitude; docs/displacement.md §6, §9); empty: the square tile's alone (a quarter of "
                             "the ball's precomputation)")
    parser.add_argument("--curved-view-horizon", type=float, default=88.0,
                        help="the ball's and the torus's S also at views on the horizon, evaluated at this polar "
                             "angle (degrees; docs/displacement.md §6, §9); 0: S clamped beyond its outermost bins")
    parser.add_argument("--planar-view-horizon", type=float, default=0.0,
                        help="the planar maps' S also at views on the horizon, evaluated at this polar angle "
                             "(degrees; as --curved-view-horizon; section 4's view grazes them beyond S's outermost "
                             "bins); 0: S clamped there, the chapter's")
    parser.add_argument("--lod-footprint", choices=sorted(LOD_FOOTPRINT), default="narrow",
                        help="section 4: which width of a pixel's footprint picks the mipmap's levels (the scene's "
                             "\"footprint\"; docs/displacement.md §8): narrow (across the view) or area (the square "
                             "root of its area, coarser toward the horizon)")
    parser.add_argument("--periodic-tables", choices=["none", "tiled", "all"], default="none",
                        help="tables of the map as a tile among its copies (vdb_displacement_prefilter --periodic): "
                             "none (the chapter's, the map alone), tiled (those of the images that show the map "
                             "tiled: the ball's and the torus's, and sections 4-5's) or all (the "
                             "planes' lone tile too); docs/displacement.md §6")
    parser.add_argument("--curved-tables", action=argparse.BooleanOptionalAction, default=True,
                        help="the ball's and the torus's tables over a base as convex as theirs (the ball's 1 / radius, "
                             "the torus's outer half's mean curvature; docs/displacement.md §6); --no-curved-tables: "
                             "over a plane, the chapter's")
    parser.add_argument("--relief-radius", type=int, default=2,
                        help="the ball's and the torus's tables with the relief term over h_low's (2 R + 1)^2 cells "
                             "about each, at most the coarse map's (docs/displacement.md §6, \"The relief term\"); "
                             "0: the chapter's T S. The planar maps keep T S: their images see the cells as the "
                             "tables' bins do (§9)")
    parser.add_argument("--torus-cells", type=int, default=128, help="of the torus's map (surface \"torus\")")
    parser.add_argument("--scale-tiles", type=int, default=16, help="section 5's tiles per side; 0: no section 5")
    parser.add_argument("--scale-spp", default="16,64")
    parser.add_argument("--scale-spp-ref", type=int, default=2048)
    parser.add_argument("--ball-scale-cells", type=int, default=512,
                        help="of the ball's map in section 5 (0: the ball is left out of it)")
    parser.add_argument("--ball-scale-tiles", default="8,52",
                        help="tiles around the ball's equator in section 5, T x T/2 in all (even counts)")
    parser.add_argument("--ball-scale-res", default="128x96", help="of the ball's images in section 5")
    parser.add_argument("--table-seeds", default="1",
                        help="seeds of the full model's tables (vdb_displacement_prefilter --seed), e.g. 1,2,3,4,5: "
                             "sections 1-2 also make and render them and report the full model's error over them")
    parser.add_argument("--resume", action="store_true",
                        help="skip each map and render that an earlier run into --out made with the same command from "
                             "files that have not changed since (make's rule; scripts/resumable.py): an interrupted run "
                             "goes on where it stopped. `make displacement` passes it. The tables are reused whenever "
                             "an earlier run made them with the same settings, with or without it")
    parser.add_argument("--no-study", action="store_true", help="leave out sections 1-3 (to run sections 4-5 alone)")
    parser.add_argument("--no-chapter-scales", action="store_true",
                        help="sections 1-3 at --factors only, not also at each surface's scale in the chapter "
                             f"(Table 4.3: {CHAPTER_SCALES_TEXT})")
    args = parser.parse_args()
    try:
        args.seeds = [int(seed) for seed in args.table_seeds.split(",")]
    except ValueError:
        args.seeds = [0]
    if args.seeds[0] != 1 or len(set(args.seeds)) != len(args.seeds) or min(args.seeds) < 1:
        parser.error(f"--table-seeds {args.table_seeds!r}: distinct positive seeds, the first 1 (the run's own tables)")
    if not args.lighting or any(l not in LIGHTING for l in args.lighting.split(",")):
        parser.error(f"--lighting {args.lighting!r}: a comma-separated list of {', '.join(LIGHTING)}")
    try:
        tile_counts = ball_scale_tiles(args)
    except ValueError:
        tile_counts = [0]
    if any(t < 2 or t % 2 for t in tile_counts):
        parser.error(f"--ball-scale-tiles {args.ball_scale_tiles!r}: a comma-separated list of even tile counts")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.time()
    args.rendered, args.resumed, args.reported_tables = set(), [], set()
    rows, timing_rows, lod_rows, scale_rows = [], [], [], []
    for surface in args.surfaces.split(","):
        make_map(args, map_kind(surface), map_cells(args, surface), out / f"{surface}.exr")
        if surface == "torus":
            write_torus(out / TORUS["placement"]["mesh"])
        for factor in [] if args.no_study else study_factors(args, surface):
            study(args, out, surface, factor, rows, timing_rows)
        if surface not in CURVED:  # sections 4-5 view tiles on a plane, where they are instances
            if args.lod_spp:
                level_of_detail(args, out, surface, lod_rows, timing_rows)
            if args.scale_tiles > 0:
                chapter_scale(args, out, surface, scale_rows, timing_rows)
        elif surface == "ball" and args.scale_tiles > 0 and args.ball_scale_cells > 0:
            ball_at_scale(args, out, scale_rows, timing_rows)
    write_report(args, out, rows, timing_rows, lod_rows, time.time() - start, scale_rows)
    gated = [r for r in rows if r["passed"] is not None]
    print(f"{out / 'report.md'}: {sum(r['passed'] for r in gated)} of {len(gated)} gates pass")


if __name__ == "__main__":
    main()
