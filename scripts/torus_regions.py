"""Where on a torus an image's light lies: masks of the pixels whose camera ray meets the base torus
in shadow (beyond its terminator or in the torus's own cast shadow), lit under a grazing or a high
sun on its outer half (both curvatures of one sign: convex) or its inner half (a saddle), and of
those that miss it (what a displaced shell shows past the base torus's silhouette). Used by
displacement_experiment.py to split the torus's error (docs/displacement.md §9), as
sphere_regions.py splits the ball's.

The base torus is the analytic one (ring radius R around the z axis through `centre`, tube radius
r), found by sphere tracing its distance function; the experiment's mesh of 96 x 48 quads departs
from it by under 0.3% of the tube's radius."""
import math

import pinhole_pixels
from sphere_regions import SILHOUETTE, SUN_BANDS

GRAZING = SUN_BANDS[1][2]  # the cosine below which the sun grazes, as on the sphere
IN_SHADOW = "in shadow (beyond the terminator or the torus's own shadow)"
REGIONS = [IN_SHADOW] + [f"{sun}, {half}" for sun in ("grazing sun (cos < %.2f)" % GRAZING,
                                                        "high sun (cos >= %.2f)" % GRAZING)
                         for half in ("outer half (convex)", "inner half (saddle)")] + [SILHOUETTE]


def _distance(p, ring, tube):
    """The signed distance from p (relative to the centre) to the torus."""
    return math.hypot(math.hypot(p[0], p[1]) - ring, p[2]) - tube


def _march(origin, d, ring, tube, t_max):
    """The distance along the unit d at which a ray from origin meets the torus, or None."""
    t = 0.0
    for _ in range(400):
        step = _distance([o + t * x for o, x in zip(origin, d)], ring, tube)
        if step < 1e-6 * tube:
            return t
        t += step
        if t > t_max:
            return None
    return None


def _normal(p, ring):
    """The torus's outward unit normal at p on it: from the tube's centre line through p."""
    rho = math.hypot(p[0], p[1])
    v = [p[0] - ring * p[0] / rho, p[1] - ring * p[1] / rho, p[2]]
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def _region(offset, d, ring, tube, toward_sun):
    """The index in REGIONS of the pixel whose ray from `offset` (relative to the centre) runs along d."""
    t_max = math.sqrt(sum(o * o for o in offset)) + 2 * (ring + tube)
    t = _march(offset, d, ring, tube, t_max)
    if t is None:
        return len(REGIONS) - 1
    p = [o + t * x for o, x in zip(offset, d)]
    n = _normal(p, ring)
    cos_sun = sum(a * b for a, b in zip(n, toward_sun))
    if cos_sun <= 0:
        return 0
    lifted = [a + 1e-4 * tube * b for a, b in zip(p, n)]
    if _march(lifted, toward_sun, ring, tube, 2 * (ring + tube) + 2 * tube) is not None:
        return 0
    outer = math.hypot(p[0], p[1]) >= ring
    return 1 + 2 * (cos_sun >= GRAZING) + (0 if outer else 1)


def region_masks(out, tag, camera, centre, ring, tube, sun_travel, width, height):
    """Writes out/{tag}_region{k}.pfm for each of REGIONS; returns [(name, path, pixel count)]."""
    toward_sun = pinhole_pixels.toward(sun_travel)
    return pinhole_pixels.region_masks(
        out, tag, camera, centre, REGIONS, width, height,
        lambda offset, d: _region(offset, d, ring, tube, toward_sun))
