"""The pixels of vdb_render's pinhole camera (render/camera.cpp: vertical field of view, pixel (x, y)
from the top left, rays through the pixels' centres) and masks of them, for the experiments that
split an image's error by what its pixels see (modularity_experiment.py, sphere_regions.py,
torus_regions.py)."""
import math
import pathlib
import struct


def _normalized(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def pixel_rays(position, target, up, fov, width, height):
    """(x, y, origin, unit direction) of every pixel's centre ray."""
    forward = _normalized([t - p for t, p in zip(target, position)])
    right = _normalized(_cross(forward, up))
    true_up = _cross(right, forward)
    tan_half, aspect = math.tan(math.radians(fov) / 2), width / height
    for y in range(height):
        for x in range(width):
            sx = (2 * (x + 0.5) / width - 1) * tan_half * aspect
            sy = (1 - 2 * (y + 0.5) / height) * tan_half
            yield x, y, position, _normalized([f + sx * r + sy * u for f, r, u in zip(forward, right, true_up)])


def write_mask_pfm(path, width, height, pixels):
    """A PFM image (vdb_image_compare --mask) of 1 at the (x, y) in `pixels`, 0 elsewhere."""
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (width, height))
        for y in reversed(range(height)):  # PFM rows go bottom to top
            for x in range(width):
                v = 1.0 if (x, y) in pixels else 0.0
                f.write(struct.pack("<3f", v, v, v))


def region_masks(out, tag, camera, centre, names, width, height, region_of):
    """Sorts the camera's pixels into the regions `names` by region_of(origin relative to `centre`, unit
    direction) (an index into names) of their centre rays; writes out/{tag}_region{k}.pfm for each;
    returns [(name, path, pixel count)]."""
    pixels = [set() for _ in names]
    for x, y, origin, d in pixel_rays(camera["position"], camera["target"], camera["up"], camera["fov"], width,
                                      height):
        pixels[region_of([o - c for o, c in zip(origin, centre)], d)].add((x, y))
    regions = []
    for k, name in enumerate(names):
        path = pathlib.Path(out) / f"{tag}_region{k}.pfm"
        write_mask_pfm(path, width, height, pixels[k])
        regions.append((name, path, len(pixels[k])))
    return regions


def toward(travel):
    """The unit vector against a light's direction of travel: toward the light."""
    return _normalized([-x for x in travel])
