"""Where on a sphere an image's light lies: masks of the pixels whose camera ray meets the sphere
beyond its terminator, under a grazing sun, under a high sun, and of those that miss it (what a
displaced shell shows past the base sphere's silhouette). Used by displacement_experiment.py to
split the ball's error (docs/displacement.md §9)."""
import math

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
    toward_sun = pinhole_pixels.toward(sun_travel)
    names = [b[0] for b in SUN_BANDS] + [SILHOUETTE]
    return pinhole_pixels.region_masks(
        out, tag, camera, centre, names, width, height,
        lambda offset, d: _region(offset, d, radius, toward_sun))
