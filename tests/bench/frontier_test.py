#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""bench/frontier/frontier (issue 17): the quick grid runs and reports (the reference's errors
against itself are zero, a held-update point has a finite error, a point beyond the stability
limit is a row "unstable at step N", the plots are PNGs); bad grids stop with one line naming the
key; a run stopped by a signal is not kept as a failure; on a machine without the run folders the
record beside the report gives the same rows, but not for a point whose knobs changed; the
committed record of the full grid restores every point it holds; a point with another pillar
wall than the reference's is also measured against the reference with its wall.
Usage: frontier_test.py SOURCE_DIR"""
import csv
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

SOURCE = sys.argv.pop(1) if len(sys.argv) > 1 else "."
FRONTIER = os.path.join(SOURCE, "bench/frontier/frontier")


def frontier(*args):
    return subprocess.run([FRONTIER, *args], capture_output=True, text=True, timeout=900)


def rows(report, problem):
    """setting -> cells of the problem's table."""
    text = report.split(f"### {problem} ")[1].split("###")[0]
    return {c[0]: c for c in ([x.strip() for x in line.strip("|").split("|")]
                              for line in text.splitlines() if line.startswith("| ")
                              and not line.startswith("| setting"))}


class QuickGrid(unittest.TestCase):
    def test_runs_and_reports(self):
        with tempfile.TemporaryDirectory() as d:
            r = frontier("--quick", "--out", d, "--jobs", "2")
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            with open(os.path.join(d, "quick", "frontier.md")) as f:
                report = f.read()
            for problem in ("dilute-d6.0-ca0.2", "dense3"):
                t = rows(report, problem)
                self.assertEqual(t["reference"][2], "ok", t)
                self.assertEqual(float(t["reference"][4]), 0.0)  # the finest point against itself
                self.assertEqual(t["held2"][2], "ok", t)
                err = float(t["held2"][4])
                self.assertTrue(0 <= err < 0.05, err)
                self.assertGreater(float(t["held2"][9]), 0)  # wall seconds per pillar
                self.assertRegex(t["re1"][2], r"^unstable at step \d+")
                png = os.path.join(d, "quick", "frontier", f"frontier-{problem}.png")
                with open(png, "rb") as f:
                    self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
            self.assertIn("## The cheapest setting within tolerance", report)
            # The stability problem: Re 0.25 runs its 300 steps, Re 1 does not (the envelope).
            t = rows(report, "hard3")
            self.assertEqual(t["reference"][2], "ok: ran 300 steps", t)
            self.assertRegex(t["re1"][2], r"^unstable at step \d+")
            self.assertRegex(report, r"\| 0\.8 \| 0\.25 \| 1\.0: unstable at step \d+")
            # A second call reads the finished points back instead of running them again.
            again = frontier("--quick", "--out", d, "--jobs", "2")
            self.assertEqual(again.returncode, 0, again.stderr)
            with open(os.path.join(d, "quick", "frontier.md")) as f:
                self.assertEqual(rows(f.read(), "dense3")["held2"], rows(report, "dense3")["held2"])
            self.new_machine(os.path.join(d, "quick"), report)

    def new_machine(self, done, report):
        """Only the report's folder (the record among its figures) moves to the new machine."""
        with tempfile.TemporaryDirectory() as d:
            shutil.copytree(os.path.join(done, "frontier"), os.path.join(d, "frontier"))
            with open(os.path.join(SOURCE, "configs/frontier/quick.toml")) as f:
                grid = f.read()
            changed = os.path.join(d, "quick.toml")  # the record is the grid's: same file name
            with open(changed, "w") as f:
                f.write(grid.replace('name = "held2"\nforce_every = 2', 'name = "held2"\nforce_every = 3'))
            for path, held2_restored in ((os.path.join(SOURCE, "configs/frontier/quick.toml"), True),
                                         (changed, False)):
                r = frontier("--grid", path, "--out", os.path.join(d, "runs"), "--report-only",
                             "--report", os.path.join(d, "frontier.md"))
                self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
                with open(os.path.join(d, "frontier.md")) as f:
                    again = f.read()
                self.assertRegex(again, r"\d+ results are restored from `.*quick-results.csv`")
                for problem in ("dilute-d6.0-ca0.2", "dense3", "hard3", "capsule-ca0.2"):
                    old, new = rows(report, problem), rows(again, problem)
                    for point in ("reference", "mrt", "re1"):
                        self.assertEqual(new[point], old[point], (problem, point))
                    if held2_restored:
                        self.assertEqual(new["held2"], old["held2"], problem)
                    else:  # force_every 3 is not the point that was run
                        self.assertEqual(new["held2"][2], "not run", problem)


class CommittedRecord(unittest.TestCase):
    def test_restores_every_recorded_point_of_the_full_grid(self):
        """docs/frontier/full-results.csv stands for its points after knobs were added to the grid
        (their defaults are what those points ran with): no recorded point reports "not run"."""
        with tempfile.TemporaryDirectory() as d:
            record = os.path.join(d, "full-results.csv")
            shutil.copy(os.path.join(SOURCE, "docs/frontier/full-results.csv"), record)
            with open(record, newline="") as f:
                recorded = [(r["problem"], r["point"]) for r in csv.DictReader(f)]
            r = frontier("--grid", os.path.join(SOURCE, "configs/frontier/full.toml"), "--out",
                         os.path.join(d, "runs"), "--report-only", "--report",
                         os.path.join(d, "frontier.md"), "--figures", d, "--record", record)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            with open(os.path.join(d, "frontier.md")) as f:
                report = f.read()
            self.assertGreater(len(recorded), 60)
            for problem, point in recorded:
                status = rows(report, problem)[point][2]
                self.assertNotEqual(status, "not run", (problem, point))


GOOD = """
[reference]
dx_um = 0.8
mesh_faces = 500
reynolds = 0.25
ib_kernel = "peskin4"
force_every = 1
viscosity_field_every = 1
[[problem]]
name = "dilute"
kind = "dilute"
row_shift_um = 6.0
capillary_number = 0.2
columns = [1, 2]
"""


class StoppedRuns(unittest.TestCase):
    def test_a_run_stopped_by_a_signal_is_not_a_failure(self):
        # A point whose program a stop killed (long-runs stop, Ctrl-C) runs again next time; one
        # that exited with an error keeps its "failed" row.
        sys.path.insert(0, os.path.join(SOURCE, "bench/frontier"))
        import point_run
        for code, stopped in ((-2, True), (-9, True), (130, True), (0, False), (1, False), (2, False)):
            self.assertEqual(point_run._interrupted(code), stopped, code)


class WallForWall(unittest.TestCase):
    def test_a_point_with_another_wall_is_measured_against_the_reference_of_that_wall(self):
        sys.path.insert(0, os.path.join(SOURCE, "bench/frontier"))
        import grid
        import report
        points = ('[[point]]\nname = "ref-bz"\nwall_rule = "bouzidi"\n'
                  '[[point]]\nname = "fast-bz"\nreynolds = 0.5\nwall_rule = "bouzidi"\n'
                  '[[point]]\nname = "fast"\nreynolds = 0.5\n')
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "grid.toml")
            with open(path, "w") as f:
                f.write(GOOD + points)
            g = grid.load(path)

        def run(shift, mode):
            return {"status": "ok", "shift_per_column_um": shift, "row_shift_um": 6.0, "mode": mode}
        results = {("dilute", "reference"): run(6.0, "displacement"),
                   ("dilute", "ref-bz"): run(1.0, "mixed"),
                   ("dilute", "fast-bz"): run(1.12, "mixed"),
                   ("dilute", "fast"): run(5.9, "displacement")}
        table = [line for line in report.wall_for_wall(g, results) if line.startswith("| dilute")]
        # Only fast-bz, against ref-bz: 0.12 / 6 = 0.02 of d, the same mode, within 3 %.
        self.assertEqual(table, ["| dilute | fast-bz | ref-bz | 0.02 | mixed | yes |"])
        results[("dilute", "fast-bz")] = run(1.12, "zigzag")  # the mode lost: not within
        self.assertTrue(report.wall_for_wall(g, results)[-2].endswith("| no |"))
        results[("dilute", "ref-bz")] = {"status": "not run"}  # nothing to compare with
        self.assertEqual(report.wall_for_wall(g, results), [])


class BadGrid(unittest.TestCase):
    def expect_refused(self, text, *words):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "grid.toml")
            with open(path, "w") as f:
                f.write(text)
            r = frontier("--grid", path, "--out", d, "--report-only", "--report",
                         os.path.join(d, "f.md"))
            self.assertNotEqual(r.returncode, 0)
            line = r.stderr.strip()
            self.assertEqual(len(line.splitlines()), 1, line)
            self.assertTrue(line.startswith(f"frontier: error: {path}"), line)
            for w in words:
                self.assertIn(w, line)

    def test_unknown_knob(self):
        self.expect_refused(GOOD + '[[point]]\nname = "x"\ntimestep = 2\n', "unknown knob 'timestep'")

    def test_value_outside_a_knobs_range(self):
        self.expect_refused(GOOD + '[[point]]\nname = "x"\nforce_every = 0\n', "'force_every' = 0",
                            "steps 1..1000")
        self.expect_refused(GOOD + '[[point]]\nname = "x"\nib_kernel = "gauss"\n', "ib_kernel")
        self.expect_refused(GOOD + '[[point]]\nname = "x"\nspread_held = 1\n', "'spread_held' = 1",
                            "true or false")

    def test_reference_must_name_every_knob(self):
        self.expect_refused(GOOD.replace("force_every = 1\n", ""), "[reference]", "force_every")

    def test_bad_problem(self):
        self.expect_refused(GOOD.replace("columns = [1, 2]", "columns = [3, 2]"), "'columns'")
        self.expect_refused(GOOD.replace('kind = "dilute"', 'kind = "dense"').replace("columns = [1, 2]", ""),
                            "missing 'cells'")
        self.expect_refused(GOOD + "colour = 1\n", "unknown key 'colour'")

    def test_unknown_point_in_only(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "grid.toml")
            with open(path, "w") as f:
                f.write(GOOD)
            r = frontier("--grid", path, "--out", d, "--only", "dilute/fast", "--report",
                         os.path.join(d, "f.md"))
            self.assertNotEqual(r.returncode, 0)
            self.assertEqual(r.stderr.strip(), "frontier: error: --only: 'dilute/fast': no point "
                             "'fast' in the grid (points: reference)")

    def test_malformed_record(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "grid.toml")
            with open(path, "w") as f:
                f.write(GOOD)
            os.makedirs(os.path.join(d, "frontier"))
            record = os.path.join(d, "frontier", "grid-results.csv")
            with open(record, "w") as f:
                f.write("problem,point,status\ndilute,reference,ok\n")
            r = frontier("--grid", path, "--out", d, "--report-only", "--report",
                         os.path.join(d, "f.md"))
            self.assertNotEqual(r.returncode, 0)
            self.assertEqual(r.stderr.strip(), f"frontier: error: {record}: line 2: expected the "
                             "columns problem, point, knobs, values, source")

    def test_not_toml(self):
        self.expect_refused("[reference\n", "not TOML")


if __name__ == "__main__":
    unittest.main(verbosity=2)
