"""Where on a sphere an image's light lies: masks of the pixels whose camera ray meets the sphere
beyond its terminator, under a grazing sun, under a high sun, and of those that miss it (what a
displaced shell shows past the base sphere's silhouette). Used by displacement_experiment.py to
split the ball's error (docs/displacement.md §9)."""
import math
import pathlib

import pinhole_pixels

# (name, lowest, highest cosine between the base sphere's normal and the direction toward the sun)
SUN_BANDS = [("beyond the terminator", -1.0, 0.0), ("grazing sun (cos < 0.34)", 0.0, 0.34),
             ("high sun (cos >= 0.34)", 0.34, 1.01)]
SILHOUETTE = "past the silhouette (the rim; under a sky, the sky)"


def _region(offset, d, radius, toward_sun):
    """The index of the region a ray from `offset` (relative to the centre) along d falls in."""
    b, c = sum(o * x for o, x in zip(offset, d)), sum(o * o for o in offset) - radius * radius
    if b * b - c < 0:
        return len(SUN_BANDS)
    t = -b - math.sqrt(b * b - c)
    cos_sun = sum((o + t * x) * s for o, x, s in zip(offset, d, toward_sun)) / radius
    return next(k for k, (_, low, high) in enumerate(SUN_BANDS) if low <= cos_sun < high)


def region_masks(out, tag, camera, centre, radius, sun_travel, width, height):
    """Writes out/{tag}_region{k}.pfm for each region; returns [(name, path, pixel count)]."""
    toward_sun = [-x for x in sun_travel]
    toward_sun = [x / math.sqrt(sum(v * v for v in toward_sun)) for x in toward_sun]
    names = [b[0] for b in SUN_BANDS] + [SILHOUETTE]
    pixels = [set() for _ in names]
    for x, y, origin, d in pinhole_pixels.pixel_rays(camera["position"], camera["target"], camera["up"],
                                                     camera["fov"], width, height):
        pixels[_region([o - c for o, c in zip(origin, centre)], d, radius, toward_sun)].add((x, y))
    regions = []
    for k, name in enumerate(names):
        path = pathlib.Path(out) / f"{tag}_region{k}.pfm"
        pinhole_pixels.write_mask_pfm(path, width, height, pixels[k])
        regions.append((name, path, len(pixels[k])))
    return regions
