"""An OpenCV tracker in carfollow's loop, against the paper's tracker, on the scenario library.

    pip install ./sim/python opencv-contrib-python-headless
    python examples/python/opencv_tracker.py [--kind csrt|kcf] [--duration S] [SCENARIO ...]

The OpenCV tracker starts on the box where the scenario puts the target at t = 0 (the
teleoperator's placement of the paper's section 2.2) and follows it; the box's width gives
the scale, the scale the range (the target is ``camera.target_size_px`` wide at
``camera.target_nominal_range_m``), and its centre the lateral offset by the pinhole model.
The built-in controller drives on whichever tracker's estimates, 128 ms late as always.
Each run's outputs go to renders/opencv/<tracker>/<scenario>/; a Markdown table to stdout.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import cv2
import numpy as np

import carfollow


class OpenCvTracker:
    """cv2's CSRT or KCF tracker as a carfollow tracker."""

    def __init__(self, kind: str = "csrt") -> None:
        self.kind = kind
        self.name = f"OpenCV {kind.upper()}"  # in summary.json and the table
        self.tracker = None
        self.camera = None
        self.box = None  # (x, y, w, h), from reset until the first frame
        self.width0 = None  # the box's width at scale 1
        self.misses = 0

    def _make(self):
        if self.kind == "csrt":
            return cv2.TrackerCSRT_create()
        return cv2.TrackerKCF_create()

    def reset(self, camera: carfollow.Camera, start: carfollow.Estimate | None) -> None:
        if start is None or start.cx is None or start.scale is None:
            raise ValueError("the OpenCV tracker needs the target's starting box")
        self.camera = camera
        w, h = camera.target_size_px
        w, h = w * start.scale, h * start.scale
        self.box = (start.cx - w / 2, start.cy - h / 2, w, h)
        self.width0 = w / start.scale
        self.tracker = None
        self.misses = 0

    def _estimate(self, x: float, y: float, w: float, h: float, status: str) -> carfollow.Estimate:
        cam = self.camera
        cx, cy = x + w / 2, y + h / 2
        scale = w / self.width0
        rng = cam.target_nominal_range_m / scale
        (fx, fy), (c0x, c0y) = cam.focal_px, cam.image_center_px
        return carfollow.Estimate(
            range_m=rng,
            lateral_m=(cx - c0x) * rng / fx,
            cx=cx,
            cy=cy,
            scale=scale,
            status=status,
            vertical_m=(cy - c0y) * rng / fy,
        )

    def track(self, frame: np.ndarray, t: float, camera: carfollow.Camera):
        self.camera = camera
        bgr = cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR)
        if self.tracker is None:
            self.tracker = self._make()
            x, y, w, h = self.box
            self.tracker.init(bgr, (int(round(x)), int(round(y)), int(round(w)), int(round(h))))
            return self._estimate(x, y, w, h, "tracking")
        ok, (x, y, w, h) = self.tracker.update(bgr)
        if not ok or w <= 0:
            self.misses += 1
            if self.misses < 8:
                return None  # coasting: the controller hears nothing new
            x, y, w, h = self.box
            return self._estimate(x, y, w, h, "lost")
        self.misses = 0
        self.box = (x, y, w, h)
        return self._estimate(x, y, w, h, "tracking")


def row(summary: dict) -> str:
    gap = summary["gap_m"]
    p95 = summary["range_error_m"]["p95_abs"]
    return (
        f"| {summary['scenario']} | {summary['tracker']} | "
        f"{'pass' if summary['passed'] else 'FAIL'} | {summary['tracking_lost_s']:.1f} | "
        f"{gap['min']:.1f}–{gap['max']:.1f} | {'–' if p95 is None else f'{p95:.2f}'} |"
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenarios", nargs="*", help="names or paths (default: the library)")
    ap.add_argument("--kind", choices=["csrt", "kcf"], default="csrt")
    ap.add_argument("--duration", type=float, help="seconds of each scenario to run")
    ap.add_argument("--out", default="renders/opencv")
    args = ap.parse_args()
    names = args.scenarios or carfollow.shipped_scenarios()
    overrides = {"duration_s": args.duration} if args.duration else None
    print("| scenario | tracker | verdict | lost s | gap m | range error p95 m |")
    print("|---|---|---|---|---|---|")
    for name in names:
        for label, tracker in [("paper", None), (args.kind, OpenCvTracker(args.kind))]:
            sim = carfollow.Simulation(name, overrides=overrides, tracker=tracker)
            out = Path(args.out) / label / sim.name
            print(row(sim.run(out=out)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
