#!/usr/bin/env python3
"""scripts/table_draw.py: the S bins a planar image reads under a sun, and how far their draw moves
its mean."""

import math
import pathlib
import random
import sys
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))

import pinhole_pixels  # noqa: E402
import table_draw  # noqa: E402

DOWN = {"position": [0.5, 0.5, 2.0], "target": [0.5, 0.5, 0.0], "up": [0, 1, 0], "fov": 0.5}
EXPERIMENT = {"position": [-0.55, -1.25, 1.05], "target": [0.5, 0.5, 0], "up": [0, 0, 1], "fov": 34}
SUN = [0.62, -0.38, -0.69]


def square_to_hemisphere(u):
    """math/concentric_mapping.h's squareToHemisphere, to round-trip the Python inverse against."""
    a, b = 2 * u[0] - 1, 2 * u[1] - 1
    if a == 0 and b == 0:
        return [0.0, 0.0, 1.0]
    if abs(a) > abs(b):
        r, phi = a, math.pi / 4 * (b / a)
    else:
        r, phi = b, math.pi / 2 - math.pi / 4 * (a / b)
    x, y = r * math.cos(phi), r * math.sin(phi)
    r2 = min(1.0, x * x + y * y)
    return [x * math.sqrt(2 - r2), y * math.sqrt(2 - r2), 1 - r2]


class ConcentricSquare(unittest.TestCase):
    def test_zenith_and_horizon(self):
        self.assertEqual(table_draw.hemisphere_to_square([0, 0, 1]), (0.5, 0.5))
        u = table_draw.hemisphere_to_square([1, 0, 0])
        self.assertAlmostEqual(u[0], 1.0)
        self.assertAlmostEqual(u[1], 0.5)

    def test_round_trip_over_the_square(self):
        rng = random.Random(1)
        for _ in range(1000):
            u = (rng.random(), rng.random())
            back = table_draw.hemisphere_to_square(square_to_hemisphere(u))
            self.assertAlmostEqual(back[0], u[0], places=9)
            self.assertAlmostEqual(back[1], u[1], places=9)


class BinsRead(unittest.TestCase):
    def test_each_pixel_spreads_one_unit_of_weight(self):
        weights = table_draw.bins_read(EXPERIMENT, SUN, 15, 48, 36)
        seeing = 0
        for _, _, o, d in pinhole_pixels.pixel_rays(EXPERIMENT["position"], EXPERIMENT["target"], EXPERIMENT["up"],
                                                     EXPERIMENT["fov"], 48, 36):
            t = -o[2] / d[2] if d[2] < 0 else -1
            seeing += t > 0 and all(0 <= o[k] + t * d[k] <= 1 for k in range(2))
        self.assertGreater(seeing, 100)
        self.assertAlmostEqual(sum(weights.values()), seeing, places=9)

    def test_a_narrow_view_down_under_a_zenith_sun_reads_one_bin_whole(self):
        # N odd: the zenith is bin 7's centre on both axes, for wi and for wo (one pixel, straight down).
        weights = table_draw.bins_read(DOWN, [0, 0, -1], 15, 1, 1)
        self.assertEqual(set(weights), {(7, 7, 7, 7)})
        self.assertAlmostEqual(table_draw.image_spread(0.03, weights), 0.03)

    def test_the_experiment_view_averages_some_bins_and_not_all(self):
        weights = table_draw.bins_read(EXPERIMENT, SUN, 15, 48, 36)
        n = table_draw.effective_bins(weights)
        self.assertGreater(n, 4)          # more than the sun's four
        self.assertLess(n, len(weights))  # fewer than it reads: the weights are unequal


class Spread(unittest.TestCase):
    def test_equal_weights_over_k_bins(self):
        weights = {(k, 0, 0, 0): 2.5 for k in range(16)}
        self.assertAlmostEqual(table_draw.effective_bins(weights), 16)
        self.assertAlmostEqual(table_draw.image_spread(0.02, weights), 0.005)

    def test_the_spread_of_simulated_draws(self):
        # Each bin drawn with its own relative error: the weighted mean spreads as image_spread says.
        weights = table_draw.bins_read(EXPERIMENT, SUN, 15, 48, 36)
        total = sum(weights.values())
        rng = random.Random(2)
        means = [sum(w * (1 + rng.gauss(0, 0.03)) for w in weights.values()) / total for _ in range(4000)]
        mu = sum(means) / len(means)
        spread = math.sqrt(sum((m - mu) ** 2 for m in means) / (len(means) - 1))
        self.assertAlmostEqual(spread / table_draw.image_spread(0.03, weights), 1.0, delta=0.05)


if __name__ == "__main__":
    unittest.main()
