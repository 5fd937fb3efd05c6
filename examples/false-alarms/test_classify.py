"""Tests of classify.py against hand-made runs.

Run: python3 -m pytest -q examples/false-alarms
"""

import csv
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import classify  # noqa: E402

COLUMNS = [
    "frame", "status", "false_alarm", "coverage_h", "coverage_v", "coverage_gain",
    "est_cx_px", "true_cx_px", "est_cy_px", "true_cy_px", "est_scale", "true_scale",
    "path_vehicle", "tracked_vehicle",
]


def row(k, false_alarm, cover, gain, dy, path="", tracked=""):
    """A frame: coverage `cover` both ways, `gain` ('' for none), the estimate `dy` px low."""
    return {
        "frame": k, "status": "coasting" if false_alarm else "tracking",
        "false_alarm": "1" if false_alarm else "0",
        "coverage_h": cover, "coverage_v": cover, "coverage_gain": gain,
        "est_cx_px": 100.0, "true_cx_px": 100.0, "est_cy_px": 80.0 + dy,
        "true_cy_px": 80.0, "est_scale": 1.02, "true_scale": 1.0,
        "path_vehicle": path, "tracked_vehicle": tracked,
    }


class Classify(unittest.TestCase):
    def run_dir(self, name, rows):
        d = os.path.join(self.tmp.name, name)
        os.makedirs(d)
        with open(os.path.join(d, "frames.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=COLUMNS)
            w.writeheader()
            for r in rows:
                w.writerow(r)
        return d

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def test_each_false_alarm_is_sorted_by_the_check_that_refused_it(self):
        paper = self.run_dir("a-paper", [
            row(0, False, 0.9, "", 0.0),         # tracking: not counted
            row(1, True, 0.2, "", 12.0),         # coverage below 0.3
            row(2, True, 0.6, 0.4, 10.0),        # a move covers more
            row(3, True, 0.6, 0.4, 9.0),
            row(4, True, 0.8, "", 0.5),          # reference or resolution
            row(5, True, 0.8, -0.2, 0.5, path="van"),  # another vehicle: left out
        ])
        robust = self.run_dir("a-robust", [row(0, True, 0.8, 0.05, 0.2)])
        c = classify.classify([paper, robust])
        self.assertEqual(len(c[("paper", classify.REASONS[0])]), 1)
        self.assertEqual(
            [round(e, 6) for e, _, _ in c[("paper", classify.REASONS[1])]], [10.0, 9.0]
        )
        self.assertEqual(len(c[("paper", classify.REASONS[2])]), 1)
        self.assertEqual(len(c[("robust", classify.REASONS[2])]), 1)
        self.assertNotIn(("robust", classify.REASONS[1]), c)
        text = classify.table(c, 3.0)
        self.assertIn("| paper | a move covers more | 2 (0.13 s) | 9.5 | 100 % | 2.0 % |", text)
        self.assertIn("| robust | reference or resolution | 1 (0.07 s) | 0.2 | 0 % |", text)

    def test_a_folder_without_frames_is_refused_in_one_line(self):
        empty = os.path.join(self.tmp.name, "empty")
        os.makedirs(empty)
        p = subprocess.run(
            [sys.executable, os.path.join(HERE, "classify.py"), empty],
            capture_output=True, text=True,
        )
        self.assertNotEqual(p.returncode, 0)
        self.assertEqual(p.stderr.strip().count("\n"), 0, p.stderr)
        self.assertIn("no frames.csv", p.stderr)


if __name__ == "__main__":
    unittest.main()
