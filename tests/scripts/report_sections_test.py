#!/usr/bin/env python3
"""scripts/displacement_experiment.py's report: each section written from its rows, in order, only where
the run measured it, with the settings that change what it shows named in its command line and text."""

import json
import pathlib
import sys
import tempfile
import types
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))

import displacement_experiment as experiment  # noqa: E402

ERRORS = {"naive": 0.012, "multi-lobe": 0.2, "full": -0.003}
STUDY_ROWS = [{"surface": "noise", "factor": 32, "lighting": light, "reference_mean": mean, "passed": True,
               "standard_error": {"naive": 0.001, "multi-lobe": 0.002, "full": 0.0005}, **ERRORS}
              for light, mean in (("gi", 0.5), ("sun", 0.3), ("sky", 0.2))]
SEEDED = dict(STUDY_ROWS[0], full_over_seeds={"errors": [-0.003, -0.001], "mean": -0.002, "deviation": 0.0014,
                                              "standard_error": 0.001},
              regions=[{"region": "high sun", "pixels": 10, "share": 0.5,
                        **{m: {"error": 0.01, "part": 0.005} for m in ERRORS}}],
              equal_time_reference={"rmse": 0.05, "spp": 16}, equal_time_full={"rmse": 0.04, "spp": 20})
TIMING = [{"surface": "noise", "factor": 32, "scaling": "interreflection",
           "seconds": {"height": 0.1, "ndfs": 20.0, "scaling": 300.0},
           "bytes": {"original_height": 4202500, "height": 4356, "svndf": 122880, "T": 192, "S": 607500},
           "ranges": {"S": {"min": 0.2, "max": 3.0, "relative_standard_error": {"median": 0.02, "p90": 0.05,
                                                                                 "p99": 0.1}}}}]
FIGURES = {"rmse": 0.08, "mean": -0.015, "spp": 11, "peak_mb": 560, "noise": 0.0123}
LOD = [{"surface": "noise", "spp": 16, "seconds": 0.25, "original": FIGURES, "mipmap": FIGURES, "models": FIGURES,
        "bands": [{"band": "near (theta_o < 70)", "pixels": 100, "share": 0.35, "original": 0.0, "mipmap": 0.01,
                   "models": 0.02}]}]
SCALE = [{"surface": "noise", "tag": "noise_scale", "spp": 16, "seconds": 1.5, "original": FIGURES,
          "models": {"8x": FIGURES, "32x": FIGURES}}]
SECTIONS = ["# Displacement-map prefiltering", "## Mean intensity", "## The full model over its tables' seeds",
            "## Global illumination by light", "## The curved surfaces' error by region", "## Equal time (global",
            "## Level of detail", "## Equal time at the chapter's scale", "## Precomputation and storage",
            "## Images"]


def arguments(**changes):
    args = dict(cells=1024, factors="8,32", rates="n15", lighting="gi,sun,sky", surfaces="noise",
                no_chapter_scales=False, seeds=[1, 2], table_seeds="1,2", periodic_tables="none",
                planar_view_horizon=0.0, lod_footprint="narrow", spp_ref=1024, spp=128, equal_time=10,
                res="192x144", resumed=[], lod_spp_ref=2048, scale_tiles=16, scale_spp_ref=2048,
                ball_scale_cells=512, ball_scale_res="128x96", ball_scale_tiles="8,52")
    return types.SimpleNamespace(**{**args, **changes})


class ReportSections(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.out = pathlib.Path(self.dir.name)

    def tearDown(self):
        self.dir.cleanup()

    def report(self, args, rows, lod=(), scale=()):
        experiment.write_report(args, self.out, rows, TIMING, list(lod), 90.0, list(scale))
        return (self.out / "report.md").read_text()

    def headings(self, text):
        return [s for s in SECTIONS if s in text]

    def test_every_section_in_order(self):
        text = self.report(arguments(), STUDY_ROWS + [SEEDED], LOD, SCALE)
        positions = [text.index(s) for s in SECTIONS]
        self.assertEqual(positions, sorted(positions))
        self.assertIn("1.5 min in all", text)
        self.assertIn("--table-seeds 1,2", text)
        self.assertIn("| noise | 32x | gi |", text)  # the noise's chapter scale is 64x
        self.assertIn("+1.20% ± 0.10%", text)  # naive with its renders' standard error
        self.assertIn("2.0% / 5.0% / 10.0%", text)  # S's bins' error
        self.assertIn("- noise_scale, 16 spp of the original:", text)
        json.loads((self.out / "report.json").read_text())

    def test_sections_only_where_measured(self):
        """Negative control: without seeds, splits, regions, level of detail or the chapter's scale, those
        sections are left out and the rest stay."""
        plain = dict(STUDY_ROWS[0], lighting="direct")
        text = self.report(arguments(seeds=[1]), [plain])
        self.assertEqual(self.headings(text), ["# Displacement-map prefiltering", "## Mean intensity",
                                               "## Equal time (global", "## Precomputation and storage", "## Images"])
        self.assertNotIn("--table-seeds", text)

    def test_level_of_detail_names_its_footprint_width(self):
        narrow = self.report(arguments(), STUDY_ROWS, LOD)
        self.assertIn("footprint picks, by its width across the view.", narrow)
        self.assertIn("| 0.0123, 0.0123, 0.0123 |", narrow)  # each field's noise
        self.assertNotIn("--lod-footprint", narrow)
        area = self.report(arguments(lod_footprint="area"), STUDY_ROWS, LOD)
        self.assertIn("footprint picks, by the square root of its area.", area)
        self.assertIn("--lod-footprint area", area)

    def test_settings_in_the_command_line(self):
        text = self.report(arguments(periodic_tables="tiled", planar_view_horizon=88.0, no_chapter_scales=True),
                           STUDY_ROWS, LOD)
        for flag in ("--periodic-tables tiled", "--planar-view-horizon 88", "--no-chapter-scales"):
            self.assertIn(flag, text)
        self.assertIn("or here its horizon nodes at 88 degrees", text)


if __name__ == "__main__":
    unittest.main()
