"""Tests of report.py against a hand-made sweep's results.

Run: python3 -m unittest discover -s examples/car-acquisition
"""

import json
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import report  # noqa: E402


def point(lens, kind, albedo, mode, seed, acquired, impact):
    """One line of a sweep's results.jsonl."""
    return {
        "seed": seed,
        "params": {
            "camera.focal_length_mm": lens,
            "actors.0.kind": kind,
            "actors.0.albedo": albedo,
            "tracker.mode": mode,
        },
        "summary": {
            "acquisition": {"range_m": acquired},
            "traffic": {"impact_speed_kph": impact},
        },
    }


class Report(unittest.TestCase):
    def write(self, points):
        f = tempfile.NamedTemporaryFile("w", suffix=".jsonl", delete=False)
        with f:
            for p in points:
                f.write(json.dumps(p) + "\n")
        self.addCleanup(os.unlink, f.name)
        return f.name

    def test_cells_give_each_seeds_first_hold_and_impact_in_order(self):
        path = self.write(
            [
                point(8.0, "sedan", 0.55, "paper", 1, 16.64, 32.4),
                point(8.0, "sedan", 0.55, "paper", 2, None, 50.0),
                point(8.0, "sedan", 0.55, "robust", 1, 20.0, None),
                point(8.0, "sedan", 0.55, "robust", 2, 21.0, None),
            ]
        )
        text = report.report(report.read(path))
        self.assertIn(
            "| sedan | 0.55 | 16.6 m / never; hit at 32 / 50 km/h | 20.0 m / 21.0 m |", text
        )
        # In all: the paper's runs hit twice and never held the vehicle once.
        self.assertIn("| 8 mm | paper | 2 | 0 | 1 |", text)
        self.assertIn("| 8 mm | robust | 2 | 2 | 0 |", text)
        # A kind not in the sweep reads as missing, not as held.
        self.assertIn("| van | 0.55 | – / –", text)

    def test_a_point_that_did_not_run_is_refused_naming_its_line(self):
        good = point(8.0, "sedan", 0.55, "paper", 1, 16.0, None)
        path = self.write([good, {"point": "x", "summary": None}])
        run = subprocess.run(
            [sys.executable, os.path.join(HERE, "report.py"), path],
            capture_output=True,
            text=True,
        )
        self.assertEqual(run.returncode, 1)
        self.assertIn(f"{path}:2: point x did not run", run.stderr)


if __name__ == "__main__":
    unittest.main()
