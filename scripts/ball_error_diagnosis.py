#!/usr/bin/env python3
"""Where the bumpy ball's error comes from (issue 23, docs/displacement.md §9): seven checks on the
tables and images of a `displacement_experiment.py` run that measured the ball (its OUT directory).

1. latitude  the ball's lit crescent (sun cosine >= 0.34, as sphere_regions.py splits it) by latitude
             bands of its base sphere: the relative error of naive and the full model in each band,
             under direct light.
2. plane     the ball's bumps map tiled 6 x 6 on a plane, lit and seen as the crescent is (theta_i,
             theta_o and the azimuth between them; the crescent's median: 60, 65 and 150 degrees),
             with the same tables: is the model right at those angles where tiles are square?
   rim-plane the same at the lit rim's angles (the view grazing at 84 and 87 degrees): is the model
             right there on a plane, where no curvature lets the bumps show more than the table holds?
   coverage  per band of the rim, the share of the camera's rays that meet the original surface and
             h_low (a black surface under a white sky): the light past the silhouette that h_low's
             outline loses whatever its BRDF.
   rim-masking R at the lit rim's angles (bench/rim_masking_study.cpp, views at 85, 87 and 89
             degrees, three draws of 2000 coarse cells): of every cell with the map in front of it,
             which the tables average, of the upper cells with nothing in front, and of every cell
             over a base as curved as the ball's, against T S there.
3. rotated   the ball with its camera and sun turned together about its centre, so that the
             crescent's light-weighted centre lies on the equator, where the tiles are square.
4. rim       the pixels past the base sphere's silhouette (sphere_regions.py's rim) by how far past
             it their camera ray passes (in radii; the farther, the more the view grazes the h_low
             it meets), under direct light: the share of the reference's light, naive and full.

Usage: scripts/ball_error_diagnosis.py OUT [--factors 8,32] [--checks latitude,plane,rotated,rim,rim-plane,coverage,rim-masking]
        [--build build] [--spp-ref 1024] [--spp 128]
Prints one line per measurement; writes its scenes, images and masks into OUT (prefixed diag_)."""
import argparse
import json
import math
import pathlib
import subprocess

import displacement_experiment as experiment
import pinhole_pixels

LATITUDE_BANDS = [(-90, 20), (20, 40), (40, 55), (55, 70), (70, 90.1)]
# How far past the base sphere's silhouette a camera ray passes, in radii.
RIM_BANDS = [(0, 0.005), (0.005, 0.01), (0.01, 0.015), (0.015, 0.02), (0.02, 1)]
# (theta_i, theta_o, azimuth between wi and wo), degrees: the crescent's median first, then its
# spread toward other views and lights.
PLANE_ANGLES = [(60, 65, 150), (60, 65, 90), (60, 65, 30), (30, 75, 150), (60, 80, 150), (50, 50, 150)]
# The lit rim's: the sun 40 degrees from the sphere's normal there (light-weighted median; quartiles
# 32 and 54), 133 degrees of azimuth from the view, which grazes.
RIM_PLANE_ANGLES = [(40, 84, 133), (40, 87, 133)]


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _normalized(v):
    n = math.sqrt(_dot(v, v))
    return [x / n for x in v]


def _rotated(v, axis, angle):  # Rodrigues' formula
    c, s, kd = math.cos(angle), math.sin(angle), _dot(axis, v)
    kv = pinhole_pixels._cross(axis, v)
    return [v[i] * c + kv[i] * s + axis[i] * kd * (1 - c) for i in range(3)]


def _render(args, out, name, scene, spp):
    path = out / f"{name}.scene.json"
    path.write_text(json.dumps(scene, indent=1))
    subprocess.run([str(v) for v in [experiment.tool(args.build, "vdb_render"), "--scene", path, "-o", out / f"{name}.exr",
                    "--spp", spp, "--max-depth", 1]], check=True, capture_output=True)
    return out / f"{name}.exr"


def _error(args, reference, image, mask=None):
    return experiment.compare(args.build, reference, image, mask=mask)["mean_relative_error"]


def _fields(manifest, placement):
    return {"reference": {"file": "ball.exr", "brdf": experiment.BRDF, **placement},
            "naive": {"file": manifest.replace(".json", ".height.exr"), "brdf": experiment.BRDF, **placement},
            "full": {"prefiltered": manifest, "scaling": True, **placement}}


def _toward_sun():
    return pinhole_pixels.toward(experiment.SUN["direction"])


def by_latitude(args, out, factor):
    camera, radius = experiment.BALL["camera"], experiment.BALL_RADIUS
    width, height = [int(v) for v in args.res.split("x")]
    sun = _toward_sun()
    bands = {band: set() for band in LATITUDE_BANDS}
    for x, y, origin, d in pinhole_pixels.pixel_rays(camera["position"], camera["target"], camera["up"],
                                                     camera["fov"], width, height):
        b, c = _dot(origin, d), _dot(origin, origin) - radius * radius
        if b * b - c < 0:
            continue
        p = [o + (-b - math.sqrt(b * b - c)) * di for o, di in zip(origin, d)]
        if _dot(p, sun) / radius < 0.34:
            continue
        latitude = math.degrees(math.asin(max(-1.0, min(1.0, p[2] / radius))))
        bands[next(band for band in LATITUDE_BANDS if band[0] <= latitude < band[1])].add((x, y))
    reference = out / "ball_direct_reference.exr"
    for band, pixels in bands.items():
        if not pixels:
            continue
        mask = out / f"diag_latitude_{band[0]}.pfm"
        pinhole_pixels.write_mask_pfm(mask, width, height, pixels)
        errors = {m: _error(args, reference, out / f"ball_{factor}x_direct_{m}.exr", mask) for m in ("naive", "full")}
        print(f"{factor}x crescent, latitude {band[0]} to {min(band[1], 90):.0f}: {len(pixels)} pixels, naive "
              f"{errors['naive']:+.2%}, full {errors['full']:+.2%}", flush=True)


def _rim_bands(args, out):
    """{band: (its pixels, its mask)} of the pixels past the silhouette by RIM_BANDS."""
    camera, radius = experiment.BALL["camera"], experiment.BALL_RADIUS
    width, height = [int(v) for v in args.res.split("x")]
    bands = {band: set() for band in RIM_BANDS}
    for x, y, origin, d in pinhole_pixels.pixel_rays(camera["position"], camera["target"], camera["up"],
                                                     camera["fov"], width, height):
        b, c = _dot(origin, d), _dot(origin, origin) - radius * radius
        if b * b - c >= 0:
            continue
        past = math.sqrt(c + radius * radius - b * b) / radius - 1  # the ray's closest approach, less the radius
        bands[next(band for band in RIM_BANDS if band[0] <= past < band[1])].add((x, y))
    masks = {}
    for band, pixels in bands.items():
        if pixels:
            masks[band] = (pixels, out / f"diag_rim_{band[0]}.pfm")
            pinhole_pixels.write_mask_pfm(masks[band][1], width, height, pixels)
    return masks


def rim(args, out, factor):
    width, height = [int(v) for v in args.res.split("x")]
    reference = out / "ball_direct_reference.exr"
    whole = experiment.compare(args.build, reference, reference)["mean_reference"]
    for band, (pixels, mask) in _rim_bands(args, out).items():
        share = experiment.compare(args.build, reference, reference, mask=mask)["mean_reference"] * len(pixels) / (
            whole * width * height)
        errors = {m: _error(args, reference, out / f"ball_{factor}x_direct_{m}.exr", mask) for m in ("naive", "full")}
        print(f"{factor}x rim, {band[0]:.3f} to {min(band[1], 1):.3f} radii past the silhouette: {len(pixels)} pixels, "
              f"{share:.1%} of the light, naive {errors['naive']:+.2%}, full {errors['full']:+.2%}", flush=True)


def coverage(args, out, factor):
    res = [int(v) for v in args.res.split("x")]
    black = {**experiment.BRDF, "specular": 0.0, "diffuse": 0.0}
    images = {}
    for model, field in _fields(f"ball_{factor}x_shadowing.json", experiment.BALL["placement"]).items():
        if model == "full":
            continue
        # A black surface under a white sky: each pixel is the share of its rays that miss the surface.
        images[model] = _render(args, out, f"diag_coverage_{factor}x_{model}",
                                {"resolution": res, "seed": 1, "camera": experiment.BALL["camera"],
                                 "lights": [{"type": "env", "radiance": 1.0}], "height_fields": [{**field, "brdf": black}]},
                                args.spp)
    for band, (pixels, mask) in _rim_bands(args, out).items():
        hit = {m: 1 - experiment.compare(args.build, image, image, mask=mask)["mean_reference"] for m, image in images.items()}
        print(f"{factor}x rim, {band[0]:.3f} to {min(band[1], 1):.3f} radii past the silhouette: the rays that meet "
              f"the original {hit['reference']:.2%}, h_low {hit['naive']:.2%} ({hit['naive'] / hit['reference'] - 1:+.1%})",
              flush=True)


def rim_masking(args, out, factor):
    # bench/rim_masking_study.cpp over windows of 64 fine cells about each coarse cell, three draws.
    for theta_i, theta_o, azimuth in [(40, t, 133) for t in (85, 87, 89)]:
        for seed in (7, 8, 9):
            result = subprocess.run([str(v) for v in [experiment.tool(args.build, "rim_masking_study"), out / "ball.exr",
                                     out / f"ball_{factor}x_shadowing.json", "--theta-i", theta_i, "--theta-o", theta_o,
                                     "--azimuth", azimuth, "--cells", 2000, "--halo", max(2, 64 // factor), "--seed", seed,
                                     "--base-curvature", 1 / experiment.BALL_RADIUS]],
                                    check=True, capture_output=True, text=True)
            print(f"{factor}x, seed {seed}: " + " ".join(result.stdout.split()), flush=True)


def on_a_plane(args, out, factor, angles=PLANE_ANGLES):
    tiles, manifest = 6, f"ball_{factor}x_shadowing.json"
    centre = [tiles / 2, tiles / 2, 0]
    direction = lambda theta, phi: [math.sin(math.radians(theta)) * math.cos(math.radians(phi)),
                                    math.sin(math.radians(theta)) * math.sin(math.radians(phi)),
                                    math.cos(math.radians(theta))]
    for theta_i, theta_o, azimuth in angles:
        wo, wi = direction(theta_o, -90), direction(theta_i, -90 + azimuth)
        camera = {"position": [c + 2.2 * w for c, w in zip(centre, wo)], "target": centre, "up": [0, 0, 1], "fov": 18}
        sun = {"type": "sun", "direction": [-x for x in wi], "strength": experiment.SUN["strength"]}
        images = {}
        for model, field in _fields(manifest, {"origin": [0, 0, 0], "tiles": [tiles, tiles]}).items():
            images[model] = _render(args, out, f"diag_plane_{factor}x_{theta_i}_{theta_o}_{azimuth}_{model}",
                                    {"resolution": [160, 120], "seed": 3, "camera": camera, "lights": [sun],
                                     "height_fields": [field]}, args.spp_ref if model == "reference" else args.spp)
        print(f"{factor}x on a plane, theta_i {theta_i}, theta_o {theta_o}, azimuth {azimuth}: naive "
              f"{_error(args, images['reference'], images['naive']):+.2%}, full "
              f"{_error(args, images['reference'], images['full']):+.2%}", flush=True)


def rotated(args, out, factor):
    camera, radius, sun = experiment.BALL["camera"], experiment.BALL_RADIUS, _toward_sun()
    centre = [0.0, 0.0, 0.0]
    count = 20000  # a Fibonacci sphere of normals
    for k in range(count):
        z, phi = -1 + 2 * (k + 0.5) / count, k * 2.399963229728653
        n = [math.sqrt(1 - z * z) * math.cos(phi), math.sqrt(1 - z * z) * math.sin(phi), z]
        view = _normalized([c - radius * x for c, x in zip(camera["position"], n)])
        if _dot(n, sun) >= 0.34 and _dot(n, view) > 0:
            centre = [a + _dot(n, sun) * _dot(n, view) * x for a, x in zip(centre, n)]
    centre = _normalized(centre)
    latitude, axis = math.asin(centre[2]), _normalized(pinhole_pixels._cross(centre, [0, 0, 1]))
    turned = {"position": _rotated(camera["position"], axis, -latitude), "target": [0, 0, 0],
              "up": _rotated(camera["up"], axis, -latitude), "fov": camera["fov"]}
    sun_light = {"type": "sun", "direction": _rotated(experiment.SUN["direction"], axis, -latitude),
                 "strength": experiment.SUN["strength"]}
    res = [int(v) for v in args.res.split("x")]
    images = {}
    for model, field in _fields(f"ball_{factor}x_shadowing.json", experiment.BALL["placement"]).items():
        images[model] = _render(args, out, f"diag_rotated_{factor}x_{model}",
                                {"resolution": res, "seed": 1, "camera": turned, "lights": [sun_light],
                                 "height_fields": [field]}, args.spp_ref if model == "reference" else args.spp)
    print(f"{factor}x, camera and sun turned so that the crescent (centre at latitude "
          f"{math.degrees(latitude):.1f}) lies on the equator: naive {_error(args, images['reference'], images['naive']):+.2%}, "
          f"full {_error(args, images['reference'], images['full']):+.2%}", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", help="a displacement_experiment.py output directory that holds the ball")
    parser.add_argument("--factors", default="8,32")
    parser.add_argument("--checks", default="latitude,plane,rotated,rim", help="of latitude, plane, rotated, rim, rim-plane, coverage, rim-masking")
    parser.add_argument("--build", default="build")
    parser.add_argument("--res", default="192x144", help="the experiment's --res")
    parser.add_argument("--spp-ref", type=int, default=1024)
    parser.add_argument("--spp", type=int, default=128)
    args = parser.parse_args()
    args.build = pathlib.Path(args.build).resolve()
    out = pathlib.Path(args.out)
    checks = {"latitude": by_latitude, "plane": on_a_plane, "rotated": rotated, "rim": rim,
              "rim-plane": lambda a, o, f: on_a_plane(a, o, f, RIM_PLANE_ANGLES), "coverage": coverage,
              "rim-masking": rim_masking}
    chosen = args.checks.split(",")
    if not set(chosen) <= set(checks):
        parser.error(f"--checks: of {', '.join(checks)}")
    for factor in [int(f) for f in args.factors.split(",")]:
        for name in chosen:
            checks[name](args, out, factor)


if __name__ == "__main__":
    main()
