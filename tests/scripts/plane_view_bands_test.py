#!/usr/bin/env python3
"""scripts/plane_view_bands.py: the level-of-detail view's pixels sorted by the view's polar angle where
their rays meet the tiled plane, the last band beyond S's outermost bin centres."""

import math
import pathlib
import sys
import tempfile
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))

import plane_view_bands as bands  # noqa: E402

CAMERA = {"position": [2.0, -0.05, 0.22], "target": [2.0, 1.2, 0.0], "up": [0, 0, 1], "fov": 40}


def ray_at(theta_degrees, x=2.0):
    """The unit direction from CAMERA's position to the plane point seen at theta_o = theta_degrees."""
    o = CAMERA["position"]
    y = o[1] + o[2] * math.tan(math.radians(theta_degrees))
    d = [x - o[0], y - o[1], -o[2]]
    n = math.sqrt(sum(v * v for v in d))
    return [v / n for v in d]


class OutermostBins(unittest.TestCase):
    def test_the_docs_angles(self):
        """docs/displacement.md §9: 78 degrees at N = 9, 83 at N = 15 (cos theta = 1 - (1 - 1/N)^2)."""
        self.assertAlmostEqual(bands.outermost_bin_degrees(9), 77.885, places=3)
        self.assertAlmostEqual(bands.outermost_bin_degrees(15), 82.595, places=3)
        self.assertEqual(bands.outermost_bin_degrees(1), 0.0)

    def test_bands_cover_the_hemisphere_without_gaps(self):
        b = bands.bands(15)
        self.assertEqual(b[0][1], 0.0)
        self.assertGreater(b[-1][2], 90.0)
        for (_, _, high), (_, low, _) in zip(b, b[1:]):
            self.assertEqual(high, low)


class Region(unittest.TestCase):
    def test_each_band_by_its_angle(self):
        o = CAMERA["position"]
        self.assertEqual(bands._region(o, ray_at(60), [4, 4], bands.bands(15)), 0)
        self.assertEqual(bands._region(o, ray_at(80), [4, 4], bands.bands(15)), 1)
        self.assertEqual(bands._region(o, ray_at(85), [4, 4], bands.bands(15)), 2)
        self.assertEqual(bands._region(o, ray_at(80), [4, 4], bands.bands(9)), 2)  # beyond N = 9's 77.9 degrees

    def test_rays_off_the_tiles_miss(self):
        """Negative controls: a ray that meets the plane past the tiles, one beside them, one upward."""
        o = CAMERA["position"]
        self.assertEqual(bands._region(o, ray_at(89), [4, 4], bands.bands(15)), 3)  # meets the plane at y = 12.6
        self.assertEqual(bands._region(o, ray_at(60, x=5.0), [4, 4], bands.bands(15)), 3)
        self.assertEqual(bands._region(o, [0.0, 0.6, 0.8], [4, 4], bands.bands(15)), 3)

    def test_masks_count_every_pixel_once(self):
        with tempfile.TemporaryDirectory() as d:
            masks = bands.region_masks(d, "t", CAMERA, [4, 4], 15, 48, 36)
            self.assertEqual(sum(count for _, _, count in masks), 48 * 36)
            self.assertTrue(all(count > 0 for _, _, count in masks))  # the view sees every band and the sky
            self.assertTrue(all(pathlib.Path(path).exists() for _, path, _ in masks))


if __name__ == "__main__":
    unittest.main()
