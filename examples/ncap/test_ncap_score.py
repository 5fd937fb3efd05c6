"""Tests of ncap_score.py's scoring rule, against cases worked by hand.

Run: python3 -m unittest discover -s examples/ncap
"""

import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ncap_score as ns  # noqa: E402


class Points(unittest.TestCase):
    def test_avoidance_earns_every_point(self):
        self.assertEqual(ns.points(0.0, 50.0), 1.0)
        self.assertEqual(ns.points(None, 50.0), 1.0)
        self.assertEqual(ns.points(0.0, 50.0, available=2.0), 2.0)

    def test_no_reduction_earns_none(self):
        self.assertEqual(ns.points(50.0, 50.0), 0.0)
        # Hitting faster than the test speed (it cannot happen, but it must not score).
        self.assertEqual(ns.points(55.0, 50.0), 0.0)

    def test_partial_points_follow_the_speed_reduction(self):
        # 50 km/h test, contact at 20 km/h: a 60 % reduction.
        self.assertAlmostEqual(ns.points(20.0, 50.0), 0.6)
        # CCRm at 50 km/h towards 20 km/h: 30 km/h closing, contact at 10 km/h: 2/3.
        self.assertAlmostEqual(ns.points(10.0, 30.0), 2.0 / 3.0)
        # With 1.5 points available, 25 km/h of 40: 1.5 × 0.375.
        self.assertAlmostEqual(ns.points(25.0, 40.0, available=1.5), 0.5625)


class Reference(unittest.TestCase):
    def test_ccrs_and_ccrm_close_at_the_speed_difference(self):
        self.assertEqual(ns.reference_speed_kph("CCRs", 35.0, 0.0), 35.0)
        self.assertEqual(ns.reference_speed_kph("CCRm", 70.0, 20.0), 50.0)

    def test_ccrb_contact_while_the_target_still_moves(self):
        # 50 km/h, 12 m, 2 m/s²: contact after sqrt(12) = 3.46 s, before the target stops
        # (6.94 s), at sqrt(2 · 2 · 12) = 6.93 m/s = 24.9 km/h.
        v = ns.reference_speed_kph("CCRb", 50.0, 50.0, gap_m=12.0, decel_mps2=2.0)
        self.assertAlmostEqual(v, math.sqrt(48.0) * 3.6)
        self.assertAlmostEqual(v, 24.94, places=2)
        # 12 m, 6 m/s²: contact after 2 s, before the stop at 2.31 s: 12 m/s = 43.2 km/h.
        v = ns.reference_speed_kph("CCRb", 50.0, 50.0, gap_m=12.0, decel_mps2=6.0)
        self.assertAlmostEqual(v, 43.2)

    def test_ccrb_contact_after_the_target_stopped(self):
        # 40 m, 6 m/s²: sqrt(80/6) = 3.65 s is after the stop at 2.31 s: the car under test
        # hits a standing target at its own 50 km/h.
        v = ns.reference_speed_kph("CCRb", 50.0, 50.0, gap_m=40.0, decel_mps2=6.0)
        self.assertEqual(v, 50.0)


class Causes(unittest.TestCase):
    def test_never_acquired(self):
        self.assertEqual(ns.loss_cause(50.0, None, 0.128, False), "never acquired")

    def test_acquired_nearer_than_the_stopping_distance(self):
        # 50 km/h: 13.89² / 14 = 13.8 m to stop at 7 m/s².
        self.assertEqual(ns.loss_cause(50.0, 13.0, 0.128, False), "acquisition range")

    def test_latency_eats_the_margin(self):
        # 13.8 m to stop, plus 13.89 × (0.128 + 0.067 + 0.292) = 6.8 m on the way.
        self.assertEqual(ns.loss_cause(50.0, 16.0, 0.128, False), "latency")

    def test_acquired_in_time_leaves_the_brake(self):
        self.assertEqual(ns.loss_cause(50.0, 25.0, 0.128, False), "braking")
        self.assertEqual(ns.loss_cause(50.0, None, 0.128, True), "braking")


class SweepRows(unittest.TestCase):
    """A sweep's row carries the overrides only: the library's file supplies the rest."""

    def row(self, overrides, collisions, acquisition_range_m=20.0):
        return {
            "scenario": "ncap-ccrs",
            "seed": 1,
            "overrides": overrides,
            "traffic": {
                "collisions": collisions,
                "acquisition_range_m": acquisition_range_m,
            },
        }

    def test_a_ccrs_row_is_read_at_its_test_speed_mode_and_lens(self):
        r = ns.row_of(self.row(
            ["chase.controller.cruise_speed_mps=8.33", 'tracker.mode="robust"',
             "camera.focal_length_mm=16.0"],
            [{"vehicle": "lead", "t_s": 9.0, "closing_kph": 12.0}],
        ))
        self.assertEqual((r["type"], r["mode"], r["lens_mm"]), ("CCRs", "robust", 16.0))
        self.assertAlmostEqual(r["v_test_kph"], 29.988)
        self.assertAlmostEqual(r["points"], 1.0 - 12.0 / 29.988)
        # 8.33 m/s: 5.0 m to stop at 7 m/s²; 20 m is beyond that and the latency's 4.1 m.
        self.assertEqual(r["cause"], "braking")

    def test_a_ccrs_row_takes_its_overlap_from_the_targets_offset(self):
        # The sweep's offsets for 75 % and 50 % (right: negative), and none for 100 %.
        for offset, overlap in [(0.46, 75), (1.0, 50), (-1.0, -50), (-0.46, -75)]:
            r = ns.row_of(self.row(
                ["chase.controller.cruise_speed_mps=8.33", f"lead.offset_m={offset}"], []))
            self.assertEqual(r["overlap_pct"], overlap)
        r = ns.row_of(self.row(["chase.controller.cruise_speed_mps=8.33"], []))
        self.assertEqual(r["overlap_pct"], 100)
        # By hand: 50 % puts the target's centre half its width to the side, so it covers
        # the car under test from its centre line out: 1.08 m of its 2.16 m.
        self.assertEqual(ns.overlap_pct(ns.TARGET_WIDTH_M / 2.0), 50)

    def test_faster_than_the_test_speed_is_no_points_and_says_so(self):
        r = ns.row_of(self.row(
            ["chase.controller.cruise_speed_mps=9.72"],
            [{"vehicle": "lead", "t_s": 5.0, "closing_kph": 52.6}],
        ))
        self.assertEqual(r["points"], 0.0)
        self.assertEqual(r["cause"], "sped up")

    def test_no_contact_without_the_target_is_marked(self):
        r = ns.row_of(self.row(["chase.controller.cruise_speed_mps=2.78"], [], None))
        self.assertEqual(r["points"], 1.0)
        self.assertEqual(r["cause"], "no contact, target never held")

    def test_a_ccrb_row_takes_its_gap_and_braking_from_the_file_and_the_axes(self):
        row = self.row(["chase.initial_gap_m=41.74", "lead.events.0.action.rate_mps2=6.0"],
                       [{"vehicle": "lead", "t_s": 5.0, "closing_kph": 25.0}])
        row["scenario"] = "ncap-ccrb"
        r = ns.row_of(row)
        self.assertEqual(r["type"], "CCRb")
        self.assertAlmostEqual(r["gap_m"], 40.0)
        self.assertEqual(r["decel_mps2"], 6.0)
        # 40 m at 6 m/s²: the target has stopped; the reference is the full 50 km/h.
        self.assertAlmostEqual(r["reference_kph"], 13.89 * 3.6)
        self.assertAlmostEqual(r["points"], 1.0 - 25.0 / (13.89 * 3.6))
        self.assertEqual(r["cause"], "braking")


if __name__ == "__main__":
    unittest.main()
