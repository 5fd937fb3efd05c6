"""A controller written in Python in carfollow's loop, on the paper's tracker's estimates.

    pip install ./sim/python
    python examples/python/python_controller.py [--duration S] [SCENARIO ...]

The controller sees what the built-in one sees: the estimate that came out of the 128 ms
delay line (range and lateral offset in the camera's frame at its capture) and the chase's
own speed, yaw rate, steering and pan-head angle. It steers on the bearing to the target
(pure pursuit on the target itself, with no breadcrumbs: it cuts corners) and keeps a
constant time gap with a PD law. With no estimate for 0.6 s it brakes gently to a stop.
Each run's outputs go to renders/python-controller/<controller>/<scenario>/.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import carfollow

WHEELBASE_M = 3.3


class BearingController:
    """Pure pursuit on the target, and a constant time-gap PD law."""

    name = "bearing pursuit and time gap (Python)"  # in summary.json and the table

    def __init__(self, standstill_m: float = 5.5, time_gap_s: float = 0.5) -> None:
        self.standstill_m = standstill_m
        self.time_gap_s = time_gap_s
        self.last = None  # (captured_t, gap)
        self.gap_rate = 0.0

    def control(self, inp: carfollow.ControlInput) -> carfollow.Command:
        est = inp.estimate
        if est is not None and inp.fresh:
            gap = math.hypot(est.range_m, est.lateral_m)
            if self.last is not None and inp.captured_t > self.last[0]:
                rate = (gap - self.last[1]) / (inp.captured_t - self.last[0])
                self.gap_rate += 0.3 * (rate - self.gap_rate)
            self.last = (inp.captured_t, gap)
        if est is None or self.last is None or inp.t - self.last[0] > 0.75:
            # Nothing heard for a while: a gentle stop.
            return carfollow.Command(0.0, 0.0, 0.3 if inp.speed_mps > 0.1 else 0.5)
        # Pure pursuit on the target: the arc through it from the rear axle.
        bearing = math.atan2(est.lateral_m, est.range_m) + inp.captured_pan_rad
        lookahead = max(self.last[1], 1.0)
        steer = math.atan2(2.0 * WHEELBASE_M * math.sin(bearing), lookahead)
        wanted = self.standstill_m + self.time_gap_s * inp.speed_mps
        target_speed = max(0.0, inp.speed_mps + self.gap_rate + 0.4 * (self.last[1] - wanted))
        dv = target_speed - inp.speed_mps
        throttle = min(1.0, 0.25 * dv) if dv > 0 else 0.0
        brake = min(1.0, -0.3 * dv) if dv < 0 else 0.0
        return carfollow.Command(max(-0.45, min(0.45, steer)), throttle, brake)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenarios", nargs="*", help="names or paths (default: the library)")
    ap.add_argument("--duration", type=float, help="seconds of each scenario to run")
    ap.add_argument("--out", default="renders/python-controller")
    args = ap.parse_args()
    overrides = {"duration_s": args.duration} if args.duration else None
    print("| scenario | controller | verdict | lost s | gap m | lateral deviation max m |")
    print("|---|---|---|---|---|---|")
    for name in args.scenarios or carfollow.shipped_scenarios():
        for label, controller in [("builtin", None), ("bearing", BearingController())]:
            sim = carfollow.Simulation(name, overrides=overrides, controller=controller)
            s = sim.run(out=Path(args.out) / label / sim.name)
            print(
                f"| {s['scenario']} | {s['controller']} | {'pass' if s['passed'] else 'FAIL'} | "
                f"{s['tracking_lost_s']:.1f} | {s['gap_m']['min']:.1f}–{s['gap_m']['max']:.1f} | "
                f"{s['lateral_path_error_m']['max_abs']:.2f} |",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
