#!/usr/bin/env python3
"""scripts/resumable.py: a rerun skips a command only while its record, outputs and inputs say it is
up to date; and the displacement experiment's renders name every file their scene reads."""

import os
import pathlib
import sys
import tempfile
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))

import displacement_experiment  # noqa: E402
import resumable  # noqa: E402


class Tool:
    """A stand-in for a tool: writes its outputs and counts its runs; fails when told to."""

    def __init__(self, outputs):
        self.outputs, self.runs, self.fail = outputs, 0, False

    def __call__(self, command):
        self.runs += 1
        for output in self.outputs:
            output.write_text(" ".join(str(c) for c in command))
        if self.fail:
            raise RuntimeError("the tool stopped halfway")
        return "done"


def age(path, seconds):
    """Sets path's time `seconds` into the past (or the future, negative)."""
    t = os.stat(path).st_mtime - seconds
    os.utime(path, (t, t))


class ResumableTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        d = pathlib.Path(self.dir.name)
        self.input = d / "map.exr"
        self.input.write_text("heights")
        age(self.input, 100)
        self.outputs = [d / "image.exr", d / "image.png"]
        self.tool = Tool(self.outputs)
        self.command = ["vdb_render", "--scene", d / "scene.json", "--spp", 16]

    def tearDown(self):
        self.dir.cleanup()

    def run_it(self, command=None, resume=True):
        return resumable.run_resumable(command or self.command, self.outputs, [self.input], resume, self.tool)

    def test_a_rerun_skips_what_is_up_to_date_and_keeps_its_seconds(self):
        stdout, first = self.run_it()
        self.assertEqual((stdout, self.tool.runs), ("done", 1))
        stdout, again = self.run_it()
        self.assertEqual((stdout, self.tool.runs), (None, 1))
        self.assertEqual(again["seconds"], first["seconds"])

    def test_without_resume_it_runs_again(self):
        self.run_it()
        self.run_it(resume=False)
        self.assertEqual(self.tool.runs, 2)

    def test_a_changed_input_runs_it_again(self):
        self.run_it()
        age(self.input, -200)  # now newer than the outputs
        self.assertEqual(self.run_it()[0], "done")
        self.assertEqual(self.tool.runs, 2)

    def test_another_command_line_runs_it_again(self):
        self.run_it()
        self.run_it(self.command[:-1] + [64])
        self.assertEqual(self.tool.runs, 2)

    def test_a_missing_output_runs_it_again(self):
        self.run_it()
        self.outputs[1].unlink()
        self.run_it()
        self.assertEqual(self.tool.runs, 2)

    def test_a_command_that_stopped_halfway_runs_again(self):
        self.run_it()
        self.tool.fail = True
        with self.assertRaises(RuntimeError):
            self.run_it(resume=False)  # its outputs are there, from the earlier run and this one
        self.assertFalse(resumable.record_path(self.outputs[0]).exists())
        self.tool.fail = False
        self.run_it()
        self.assertEqual(self.tool.runs, 3)

    def test_a_real_tool_is_run_and_then_skipped(self):
        script = "import sys; [open(p, 'w').write('x') for p in sys.argv[1:]]"
        command = [sys.executable, "-c", script, *self.outputs]
        stdout, _ = resumable.run_resumable(command, self.outputs, [self.input], True)
        self.assertEqual(stdout, "")
        stdout, _ = resumable.run_resumable(command, self.outputs, [self.input], True)
        self.assertIsNone(stdout)

    def test_an_unchanged_text_keeps_its_time(self):
        path = pathlib.Path(self.dir.name) / "scene.json"
        resumable.write_if_changed(path, "{}")
        age(path, 100)
        before = os.stat(path).st_mtime_ns
        resumable.write_if_changed(path, "{}")
        self.assertEqual(os.stat(path).st_mtime_ns, before)
        resumable.write_if_changed(path, "{\"spp\": 16}")
        self.assertNotEqual(os.stat(path).st_mtime_ns, before)
        self.assertEqual(path.read_text(), "{\"spp\": 16}")


class FieldInputsTest(unittest.TestCase):
    def test_a_scene_reads_its_map_mesh_and_each_manifest_with_its_parts(self):
        with tempfile.TemporaryDirectory() as d:
            out = pathlib.Path(d)
            for name in ["ball.exr", "torus.obj", "ball_8x_shadowing.json", "ball_8x_shadowing.S.exr",
                         "ball_8x_shadowing.stretch1.T.exr", "ball_8x_shadowing_glossy.json", "ball_32x_gi.json",
                         "ball_32x_gi.B.exr"]:
                (out / name).write_text("")
            names = lambda field: sorted(p.name for p in displacement_experiment.field_inputs(out, field))
            self.assertEqual(names({"file": "ball.exr", "mesh": "torus.obj"}), ["ball.exr", "torus.obj"])
            # Not the files of another manifest whose name begins alike.
            self.assertEqual(names({"prefiltered": "ball_8x_shadowing.json"}),
                             ["ball_8x_shadowing.S.exr", "ball_8x_shadowing.json", "ball_8x_shadowing.stretch1.T.exr"])
            self.assertEqual(names({"mipmap": ["ball_8x_shadowing.json", "ball_32x_gi.json"]}),
                             ["ball_32x_gi.B.exr", "ball_32x_gi.json", "ball_8x_shadowing.S.exr",
                              "ball_8x_shadowing.json", "ball_8x_shadowing.stretch1.T.exr"])


if __name__ == "__main__":
    unittest.main()
