#!/usr/bin/env python3
"""scripts/displacement_experiment.py's split of global illumination by light: the errors under the sun
and under the sky alone, weighted by each light's share of the reference, add up to the error under
both, because the images add."""

import pathlib
import random
import sys
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))

import displacement_experiment  # noqa: E402


def mean(image):
    return sum(image) / len(image)


def relative_error(test, reference):
    """vdb_image_compare's mean_relative_error: of the image means."""
    return mean(test) / mean(reference) - 1


def row(lighting, reference, models):
    r = {"surface": "ball", "factor": 8, "lighting": lighting, "reference_mean": mean(reference),
         "passed": None if lighting in ("sun", "sky") else True}
    r.update({name: relative_error(image, reference) for name, image in models.items()})
    return r


class LightSplit(unittest.TestCase):
    def setUp(self):
        rng = random.Random(5)
        pixels = 500
        self.reference = {"sun": [rng.uniform(0, 3) for _ in range(pixels)],
                          "sky": [rng.uniform(0, 0.6) for _ in range(pixels)]}
        # Naive too dark under the sun and too bright under the sky; the full model a little dark under both.
        gains = {"naive": {"sun": 0.96, "sky": 1.15}, "multi-lobe": {"sun": 1.3, "sky": 1.1},
                 "full": {"sun": 0.995, "sky": 0.99}}
        self.models = {light: {m: [v * rng.gauss(g[light], 0.01) for v in self.reference[light]]
                               for m, g in gains.items()} for light in ("sun", "sky")}
        both = lambda images: [a + b for a, b in zip(images["sun"], images["sky"])]
        self.rows = [row("gi", both(self.reference), {m: both({l: self.models[l][m] for l in self.models})
                                                      for m in gains}),
                     row("sun", self.reference["sun"], self.models["sun"]),
                     row("sky", self.reference["sky"], self.models["sky"])]

    def test_weighted_errors_add_up_to_the_error_under_both(self):
        [split] = displacement_experiment.light_split(self.rows)
        share = mean(self.reference["sun"]) / (mean(self.reference["sun"]) + mean(self.reference["sky"]))
        self.assertAlmostEqual(split["sun_share"], share, places=12)
        for model in ("naive", "multi-lobe", "full"):
            self.assertAlmostEqual(split[model]["sum"], split[model]["gi"], places=12)

    def test_naive_cancels(self):
        [split] = displacement_experiment.light_split(self.rows)
        naive = split["naive"]
        self.assertLess(naive["sun"], -0.03)
        self.assertGreater(naive["sky"], 0.1)
        self.assertLess(abs(naive["gi"]), abs(naive["sun"]))

    def test_an_equal_weighting_would_not_add_up(self):
        """Negative control: the shares matter (the lights are not equally bright here)."""
        [split] = displacement_experiment.light_split(self.rows)
        naive = split["naive"]
        self.assertGreater(abs((naive["sun"] + naive["sky"]) / 2 - naive["gi"]), 0.01)

    def test_no_split_without_all_three(self):
        self.assertEqual(displacement_experiment.light_split(self.rows[:2]), [])
        self.assertEqual(displacement_experiment.light_split(self.rows[1:]), [])

    def test_split_rows_have_no_gate(self):
        self.assertEqual(displacement_experiment.gate_text(None), "no gate")
        self.assertEqual(displacement_experiment.gate_text(False), "fail")
        self.assertEqual([r for r in self.rows if r["passed"] is not None], self.rows[:1])


if __name__ == "__main__":
    unittest.main()
