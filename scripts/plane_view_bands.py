"""Where on a tiled plane an image's light lies by how steeply the camera sees it: masks of the pixels
whose camera ray meets the plane z = 0 over [0, nx] x [0, ny] (the map's tiles at the origin, size 1)
with the view's polar angle theta_o below, between and beyond two angles, and of those that miss it.
The outer angle is where a prefiltered map's S table has its outermost bin centres: views beyond read
S clamped, or its horizon nodes (docs/displacement.md §6 "The view's horizon"). Used by
displacement_experiment.py to split the level-of-detail view's error (section 4, §9)."""
import math

import pinhole_pixels


def outermost_bin_degrees(n):
    """The polar angle of S's outermost bin centres at n bins per axis: the concentric square's
    coordinate 1 - 1/n taken to the hemisphere by equal area (cos theta = 1 - r^2)."""
    r = 1.0 - 1.0 / n
    return math.degrees(math.acos(1.0 - r * r))


def bands(n):
    """(name, lowest, highest theta_o in degrees) of the bands, the last beyond S's outermost bins."""
    edge = outermost_bin_degrees(n)
    return [("near (theta_o < 70)", 0.0, 70.0), (f"middle (70 to {edge:.1f})", 70.0, edge),
            (f"far (theta_o >= {edge:.1f}, beyond S's outermost bins at N = {n})", edge, 90.01)]


MISS = "off the tiles (the sky)"


def _region(origin, d, tiles, view_bands):
    """The index in view_bands (bands()) of the band a ray from `origin` along d falls in, len(view_bands)
    if it misses the tiles."""
    if d[2] >= 0:
        return len(view_bands)
    t = -origin[2] / d[2]
    x, y = origin[0] + t * d[0], origin[1] + t * d[1]
    if not (0 <= x <= tiles[0] and 0 <= y <= tiles[1]):
        return len(view_bands)
    theta = math.degrees(math.acos(-d[2]))
    return next(k for k, (_, low, high) in enumerate(view_bands) if low <= theta < high)


def region_masks(out, tag, camera, tiles, n, width, height):
    """Writes out/{tag}_region{k}.pfm for each band and the miss; returns [(name, path, pixel count)]."""
    view_bands = bands(n)
    names = [b[0] for b in view_bands] + [MISS]
    return pinhole_pixels.region_masks(out, tag, camera, [0, 0, 0], names, width, height,
                                       lambda origin, d: _region(origin, d, tiles, view_bands))
