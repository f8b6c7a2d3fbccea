#!/usr/bin/env python3
"""scripts/displacement_experiment.py --lod-footprint: section 4's mipmaps carry the scene's "footprint"
(which width of a pixel's footprint picks the levels), and the original does not."""

import json
import pathlib
import sys
import tempfile
import types
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))

import displacement_experiment as experiment  # noqa: E402


class LevelOfDetailFields(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.out = pathlib.Path(self.dir.name)
        self.fields = []
        self.saved = {name: getattr(experiment, name) for name in
                      ("prefilter", "report_tables", "render", "equal_time", "lod_bands")}
        self.saved_masks = experiment.plane_view_bands.region_masks
        manifest = self.out / "noise_8x_interreflection.json"
        manifest.write_text(json.dumps({"angular_resolution": 15}))
        experiment.prefilter = lambda args, out, surface, factor, scaling, tiled: (manifest, {})
        experiment.report_tables = lambda *a: None
        experiment.render = lambda *a, **k: (self.out / "reference.exr", 0)
        experiment.plane_view_bands.region_masks = lambda *a: []
        experiment.lod_bands = lambda *a: []
        experiment.equal_time = self.fake_equal_time

    def tearDown(self):
        for name, f in self.saved.items():
            setattr(experiment, name, f)
        experiment.plane_view_bands.region_masks = self.saved_masks
        self.dir.cleanup()

    def fake_equal_time(self, args, out, tag, fields, reference, spp, camera):
        self.fields.append(fields)
        result = {"rmse": 0.1, "mean": 0.0, "spp": spp, "peak_mb": 1}
        return 1.0, {name: dict(result) for name in fields}

    def section4(self, footprint):
        args = types.SimpleNamespace(res="8x6", factors="8", lod_spp="16", lod_spp_ref=64, rendered=set(),
                                     lod_footprint=footprint)
        rows = []
        experiment.level_of_detail(args, self.out, "noise", rows, [])
        return rows

    def test_each_mipmap_carries_the_footprint_width(self):
        for footprint in ("narrow", "area"):
            self.fields.clear()
            self.section4(footprint)
            [fields] = self.fields
            self.assertEqual(fields["mipmap"]["footprint"], footprint)
            self.assertEqual(fields["models"]["footprint"], footprint)
            self.assertNotIn("footprint", fields["original"])  # vdb_render refuses it without "mipmap"


if __name__ == "__main__":
    unittest.main()
