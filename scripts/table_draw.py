"""How far the scaling table S's random draw moves a planar image's mean under one sun
(docs/displacement.md §6, "The tables' own error"; §9, "How far the tables' draw moves the image").

On a plane every coarse cell reads S at the same directions in the map's base frame (§8): the sun's wi
for all of them, and each pixel's view wo. So the image reads few bins: the four about the sun's wi,
times those about the views of its pixels, each with its quadrilinear weight. Each bin's estimate
errs independently (each bin its own estimates, "table_sampling": 2), so the image mean's relative
spread from S's draw is
    sigma_image = sqrt(sum_b W_b^2 sigma_b^2) / sum_b W_b,
W_b the bin's summed weight over the pixels and sigma_b its relative standard error. With one error
sigma for every bin this is sigma / sqrt(n_eff), n_eff = (sum W_b)^2 / sum W_b^2: the bins' effective
number. The pixels weigh alike here (each that sees the map), a stand-in for their light."""
import math

import pinhole_pixels


def hemisphere_to_square(w):
    """math/concentric_mapping.h's hemisphereToSquare: the equal-area concentric square of w (z >= 0)."""
    scale = 1 / math.sqrt(1 + max(0.0, w[2]))
    x, y = w[0] * scale, w[1] * scale
    r, phi = math.hypot(x, y), math.atan2(y, x)
    if phi < -math.pi / 4:
        phi += 2 * math.pi
    if phi < math.pi / 4:
        a = r
        b = phi * a / (math.pi / 4)
    elif phi < 3 * math.pi / 4:
        b = r
        a = -(phi - math.pi / 2) * b / (math.pi / 4)
    elif phi < 5 * math.pi / 4:
        a = -r
        b = (phi - math.pi) * a / (math.pi / 4)
    else:
        b = -r
        a = -(phi - 3 * math.pi / 2) * b / (math.pi / 4)
    return (a + 1) / 2, (b + 1) / 2


def axis_weights(s, n):
    """prefilter/scaling_tables.cpp's axisWeights: the two bins about s in [0, 1] and the second's weight."""
    c = min(max(s * n - 0.5, 0.0), n - 1.0)
    i0 = min(int(c), max(0, n - 2))
    return i0, min(i0 + 1, n - 1), c - i0


def bins_read(camera, sun_travel, n, width, height, extent=((0.0, 1.0), (0.0, 1.0))):
    """{(ia, ib, oa, ob): summed weight} of the S bins (N = n) that an image of a plane at z = 0 over
    `extent` reads under a sun travelling along `sun_travel`, each pixel that sees the plane alike."""
    wi = pinhole_pixels.toward(sun_travel)
    sun = [axis_weights(s, n) for s in hemisphere_to_square(wi)]
    weights = {}
    for _, _, origin, d in pinhole_pixels.pixel_rays(camera["position"], camera["target"], camera["up"],
                                                     camera["fov"], width, height):
        if d[2] >= 0:
            continue
        t = -origin[2] / d[2]
        hit = [o + t * x for o, x in zip(origin, d)]
        if not all(lo <= h <= hi for h, (lo, hi) in zip(hit, extent)):
            continue
        view = [axis_weights(s, n) for s in hemisphere_to_square([-x for x in d])]
        for corner in range(16):
            index, weight = [], 1.0
            for k, (i0, i1, t_k) in enumerate(sun + view):
                upper = (corner >> k) & 1
                index.append(i1 if upper else i0)
                weight *= t_k if upper else 1 - t_k
            if weight > 0:
                weights[tuple(index)] = weights.get(tuple(index), 0.0) + weight
    return weights


def effective_bins(weights):
    """(sum W)^2 / sum W^2 of bins_read()'s weights: how many equal, independent bins they amount to."""
    total = sum(weights.values())
    return total * total / sum(w * w for w in weights.values()) if total > 0 else 0.0


def image_spread(bin_error, weights):
    """The relative spread of the image mean from S's draw, every bin of relative error bin_error."""
    n = effective_bins(weights)
    return bin_error / math.sqrt(n) if n > 0 else float("nan")
