#!/usr/bin/env python3
"""scripts/displacement_experiment.py --table-seeds: the full model's tables made again at other seeds
(vdb_displacement_prefilter --seed, named apart from the run's own) and its error summarised over them."""

import json
import math
import pathlib
import statistics
import sys
import tempfile
import types
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))

import displacement_experiment as experiment  # noqa: E402


class SeedSummary(unittest.TestCase):
    def test_mean_deviation_and_standard_error(self):
        errors = [-0.00702, -0.01010, -0.00289, -0.00100, -0.00022]  # docs §9's five woven seeds
        s = experiment.seed_summary(errors)
        self.assertAlmostEqual(s["mean"], statistics.mean(errors), places=15)
        self.assertAlmostEqual(s["deviation"], statistics.stdev(errors), places=15)
        self.assertAlmostEqual(s["standard_error"], statistics.stdev(errors) / math.sqrt(5), places=15)
        self.assertEqual(s["errors"], errors)

    def test_sample_not_population_deviation(self):
        """Negative control: dividing by n instead of n - 1 would be smaller by sqrt(4 / 5)."""
        s = experiment.seed_summary([0.0, 0.02])
        self.assertAlmostEqual(s["deviation"], math.sqrt(2) * 0.01, places=15)
        self.assertNotAlmostEqual(s["deviation"], statistics.pstdev([0.0, 0.02]), places=6)

    def test_one_seed_has_no_spread(self):
        self.assertTrue(math.isnan(experiment.seed_summary([0.01])["deviation"]))


class PrefilterSeed(unittest.TestCase):
    """prefilter() passes --seed to the tool and names the files after the seed, so that every seed's tables
    sit side by side and the run's own (seed 1) keep their names; an earlier run's files of another seed are
    not reused."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.out = pathlib.Path(self.dir.name)
        self.commands = []
        self.saved_run = experiment.run
        experiment.run = self.fake_run
        self.args = types.SimpleNamespace(build="build", rates="n15", ball_stretches="", curved_view_horizon=88.0,
                                          planar_view_horizon=0.0,
                                          curved_tables=True, relief_radius=2, cells=64, ball_cells=64, torus_cells=64,
                                          ball_scale_cells=64, periodic_tables="none")

    def tearDown(self):
        experiment.run = self.saved_run
        self.dir.cleanup()

    def fake_run(self, cmd):
        """Writes the manifest and report that vdb_displacement_prefilter would, with its --seed."""
        cmd = [str(c) for c in cmd]
        self.commands.append(cmd)
        seed = int(cmd[cmd.index("--seed") + 1]) if "--seed" in cmd else 1
        factor = int(cmd[cmd.index("--factor") + 1])
        settings = {"seed": seed, "history": " ".join(cmd), "table_sampling": experiment.TABLE_SAMPLING,
                    "edges": "periodic" if "--periodic" in cmd else "open",
                    "view_horizon_degrees": float(cmd[cmd.index("--view-horizon") + 1]) if "--view-horizon" in cmd else 0.0}
        pathlib.Path(cmd[2]).write_text(json.dumps({"factor": factor, "cells": [64 // factor], "settings": settings,
                                                    "brdf": experiment.BRDF}))
        pathlib.Path(cmd[cmd.index("--report") + 1]).write_text(json.dumps({"settings": {**settings, "seconds": {}},
                                                                             "bytes": {}, "scaling": {}}))
        return ""

    def test_seed_in_flags_and_names(self):
        manifest, report = experiment.prefilter(self.args, self.out, "noise", 8, "shadowing", seed=3)
        self.assertEqual(manifest.name, "noise_8x_shadowing_seed3.json")
        self.assertEqual(report["settings"]["seed"], 3)
        [cmd] = self.commands
        self.assertEqual(cmd[cmd.index("--seed") + 1], "3")

    def test_the_runs_own_tables_keep_their_names_and_flags(self):
        manifest, _ = experiment.prefilter(self.args, self.out, "noise", 8, "shadowing")
        self.assertEqual(manifest.name, "noise_8x_shadowing.json")
        self.assertNotIn("--seed", self.commands[0])

    def test_reused_only_at_the_same_seed(self):
        experiment.prefilter(self.args, self.out, "noise", 8, "shadowing", seed=2)
        experiment.prefilter(self.args, self.out, "noise", 8, "shadowing", seed=2)
        self.assertEqual(len(self.commands), 1)
        # Negative control: a manifest of seed 2 under seed 4's name is made again.
        (self.out / "noise_8x_shadowing_seed2.json").rename(self.out / "noise_8x_shadowing_seed4.json")
        (self.out / "noise_8x_shadowing_seed2.report.json").rename(self.out / "noise_8x_shadowing_seed4.report.json")
        experiment.prefilter(self.args, self.out, "noise", 8, "shadowing", seed=4)
        self.assertEqual(len(self.commands), 2)

    def test_periodic_tables_where_asked_and_not_reused_across_edges(self):
        """--periodic-tables: "tiled" asks the curved surfaces' tables over a periodic tile and not the
        planes'; a manifest of the other edges is made again."""
        experiment.prefilter(self.args, self.out, "noise", 8, "shadowing")
        self.args.periodic_tables = "tiled"
        experiment.prefilter(self.args, self.out, "noise", 8, "shadowing")  # reused: a plane stays open
        experiment.prefilter(self.args, self.out, "torus", 8, "shadowing")
        self.assertEqual(len(self.commands), 2)
        self.assertNotIn("--periodic", self.commands[0])
        self.assertIn("--periodic", self.commands[1])
        self.args.periodic_tables = "all"
        experiment.prefilter(self.args, self.out, "noise", 8, "shadowing")  # open before: made again
        self.assertEqual(len(self.commands), 3)
        self.assertIn("--periodic", self.commands[2])

    def test_tiled_views_of_a_plane_read_periodic_tables_of_their_own(self):
        """Under "tiled", a plane's tiled views (sections 4-5) ask tables over a periodic tile, named apart
        from the lone tile's of sections 1-2, which stay open and are reused."""
        self.args.periodic_tables = "tiled"
        lone, _ = experiment.prefilter(self.args, self.out, "woven", 8, "interreflection")
        tiled, _ = experiment.prefilter(self.args, self.out, "woven", 8, "interreflection", tiled=True)
        glossy, _ = experiment.prefilter(self.args, self.out, "woven", 8, "interreflection", tag="_glossy", tiled=True)
        self.assertEqual([lone.name, tiled.name, glossy.name], ["woven_8x_interreflection.json",
                                                                "woven_8x_interreflection_periodic.json",
                                                                "woven_8x_interreflection_glossy_periodic.json"])
        self.assertEqual(["--periodic" in c for c in self.commands], [False, True, True])
        experiment.prefilter(self.args, self.out, "woven", 8, "interreflection")  # the lone tile's: reused
        self.assertEqual(len(self.commands), 3)
        # Negative control: with no periodic tables asked, the tiled views read the lone tile's.
        self.args.periodic_tables = "none"
        again, _ = experiment.prefilter(self.args, self.out, "woven", 8, "interreflection", tiled=True)
        self.assertEqual((again.name, len(self.commands)), ("woven_8x_interreflection.json", 3))

    def test_planar_view_horizon_only_where_asked_and_not_reused_across_it(self):
        """--planar-view-horizon gives the planes' S its nodes on the view's horizon (the tool's --view-horizon);
        the curved surfaces keep --curved-view-horizon's; a plane's manifest without the nodes is made again."""
        experiment.prefilter(self.args, self.out, "woven", 8, "interreflection")
        self.assertNotIn("--view-horizon", self.commands[0])  # the default: S clamped on the planes
        self.args.planar_view_horizon = 88.0
        experiment.prefilter(self.args, self.out, "woven", 8, "interreflection", tiled=True)
        self.assertEqual(len(self.commands), 2)
        self.assertEqual(self.commands[1][self.commands[1].index("--view-horizon") + 1], "88.0")
        experiment.prefilter(self.args, self.out, "woven", 8, "interreflection")  # reused: the same nodes
        self.assertEqual(len(self.commands), 2)
        self.args.curved_view_horizon = 85.0
        experiment.prefilter(self.args, self.out, "torus", 8, "shadowing")
        self.assertEqual(self.commands[2][self.commands[2].index("--view-horizon") + 1], "85.0")

    def test_each_set_of_tables_reported_once(self):
        """report_tables: one precomputation row per manifest, whichever sections read it; sections 4-5's
        periodic tables get rows of their own."""
        self.args.reported_tables, rows = set(), []
        lone, report = experiment.prefilter(self.args, self.out, "woven", 8, "interreflection")
        experiment.report_tables(self.args, rows, "woven", 8, "interreflection", lone, report)
        experiment.report_tables(self.args, rows, "woven (level of detail)", 8, "interreflection", lone, report)
        self.assertEqual([r["surface"] for r in rows], ["woven"])
        self.args.periodic_tables = "tiled"
        tiled, report = experiment.prefilter(self.args, self.out, "woven", 8, "interreflection", tiled=True)
        experiment.report_tables(self.args, rows, "woven (level of detail)", 8, "interreflection", tiled, report)
        self.assertEqual([(r["surface"], r["tables"]) for r in rows],
                         [("woven", "woven_8x_interreflection.json"),
                          ("woven (level of detail)", "woven_8x_interreflection_periodic.json")])


if __name__ == "__main__":
    unittest.main()
