"""Where on a sphere an image's light lies: masks of the pixels whose camera ray meets the sphere
beyond its terminator, under a grazing sun, under a high sun, and of those that miss it (what a
displaced shell shows past the base sphere's silhouette), for vdb_render's pinhole camera (its
vertical field of view, pixel (x, y) from the top left, rays through the pixels' centres).
Used by displacement_experiment.py to split the ball's error (docs/displacement.md §9)."""
import math
import pathlib
import struct
import zlib

# (name, lowest, highest cosine between the base sphere's normal and the direction toward the sun)
SUN_BANDS = [("beyond the terminator", -1.0, 0.0), ("grazing sun (cos < 0.34)", 0.0, 0.34),
             ("high sun (cos >= 0.34)", 0.34, 1.01)]
SILHOUETTE = "past the silhouette (the rim; under a sky, the sky)"


def _normalized(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def write_png(path, rows):
    """An 8-bit greyscale PNG of rows of 0..255."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    header = struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 0, 0, 0, 0)
    pathlib.Path(path).write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) +
                                   chunk(b"IEND", b""))


def region_masks(out, tag, camera, centre, radius, sun_travel, width, height):
    """Writes out/{tag}_region{k}.png for each region; returns [(name, path, pixel count)]."""
    position = camera["position"]
    forward = _normalized([t - p for t, p in zip(camera["target"], position)])
    right = _normalized(_cross(forward, camera["up"]))
    up = _cross(right, forward)
    tan_half = math.tan(math.radians(camera["fov"]) / 2)
    toward_sun = _normalized([-x for x in sun_travel])
    names = [b[0] for b in SUN_BANDS] + [SILHOUETTE]
    masks = [[[0] * width for _ in range(height)] for _ in names]
    offset = [p - c for p, c in zip(position, centre)]
    for y in range(height):
        for x in range(width):
            sx = (2 * (x + 0.5) / width - 1) * tan_half * width / height
            sy = (1 - 2 * (y + 0.5) / height) * tan_half
            d = _normalized([f + sx * r + sy * u for f, r, u in zip(forward, right, up)])
            b, c = _dot(offset, d), _dot(offset, offset) - radius * radius
            if b * b - c < 0:
                masks[-1][y][x] = 255
                continue
            t = -b - math.sqrt(b * b - c)
            cos_sun = _dot(_normalized([o + t * di for o, di in zip(offset, d)]), toward_sun)
            for k, (_, low, high) in enumerate(SUN_BANDS):
                if low <= cos_sun < high:
                    masks[k][y][x] = 255
    regions = []
    for k, name in enumerate(names):
        path = pathlib.Path(out) / f"{tag}_region{k}.png"
        write_png(path, masks[k])
        regions.append((name, path, sum(v > 0 for row in masks[k] for v in row)))
    return regions
