"""What a run's false alarms are: which of the tracker's checks refused the fit, and how far
the fit lay from the target.

A false alarm (`frames.csv`'s `false_alarm`) is a frame whose status is not `tracking` while
the truth judges the estimate on the target: its centre within a quarter of the target's
width, its scale within a quarter. That tolerance is the loss's (a fit within it still
steers the chase), and it is loose enough to take in a fit one feature spacing off the
target, whose outline lies on its neighbours' edges. This sorts each false alarm on the
lead's target by the check that refused it, read from the frame's columns as the tracker
judges (`tracker::Measured::trusted`): coverage below 0.3 (the lesser of `coverage_h` and
`coverage_v`), a move of the fit covering more than 0.1 more (`coverage_gain`), else the
coverage reference or the resolution; and gives the centre's error (pixels between the
estimated and the true centre) and the scale's (relative) in each class. Frames judged on a
vehicle other than the lead (traffic) are left out: their truth columns are the lead's.

Usage:
    python3 examples/false-alarms/classify.py RUN_DIR... [--far-px 3]

Each RUN_DIR holds a run's `frames.csv`; a name ending in `-paper` or `-robust` gives its
mode (else `run`). Prints a Markdown table.
"""

import argparse
import csv
import os
import statistics
import sys

MIN_COVERAGE = 0.3
MAX_COVERAGE_GAIN = 0.1
REASONS = ("coverage below 0.3", "a move covers more", "reference or resolution")


def mode_of(run_dir):
    """The tracker mode a run folder's name ends with."""
    name = os.path.basename(os.path.normpath(run_dir))
    for mode in ("paper", "robust"):
        if name.endswith("-" + mode):
            return mode
    return "run"


def reason(row):
    """Which check refused the frame's fit."""
    cover = min(float(row["coverage_h"] or 0.0), float(row["coverage_v"] or 0.0))
    gain = float(row["coverage_gain"]) if row["coverage_gain"] else float("-inf")
    if cover < MIN_COVERAGE:
        return REASONS[0]
    if gain > MAX_COVERAGE_GAIN:
        return REASONS[1]
    return REASONS[2]


def on_the_lead(row):
    """Whether the frame is judged on the lead's target (no traffic, or the lead in the path)."""
    return row.get("path_vehicle", "") in ("", "lead") and row.get(
        "tracked_vehicle", ""
    ) in ("", "lead")


def errors(row):
    """The centre's error (px) and the scale's (relative), or None when not estimated."""
    try:
        dx = float(row["est_cx_px"]) - float(row["true_cx_px"])
        dy = float(row["est_cy_px"]) - float(row["true_cy_px"])
        ds = float(row["est_scale"]) / float(row["true_scale"]) - 1.0
    except (KeyError, ValueError, ZeroDivisionError):
        return None
    return (dx * dx + dy * dy) ** 0.5, abs(ds)


def classify(run_dirs):
    """{(mode, reason): [(centre error px, scale error, run name)]} over the runs."""
    out = {}
    for d in run_dirs:
        path = os.path.join(d, "frames.csv")
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if row.get("false_alarm") != "1" or not on_the_lead(row):
                    continue
                e = errors(row)
                if e is None:
                    continue
                key = (mode_of(d), reason(row))
                out.setdefault(key, []).append((e[0], e[1], os.path.basename(os.path.normpath(d))))
    return out


def table(classes, far_px, frame_s=1.0 / 15.0):
    """The Markdown table of `classes`."""
    lines = [
        "| mode | refused by | frames | centre error, median (px) | centre error over "
        f"{far_px:g} px | scale error, median | most in |",
        "|---|---|---|---|---|---|---|",
    ]
    for mode in ("paper", "robust", "run"):
        for r in REASONS:
            v = classes.get((mode, r))
            if not v:
                continue
            centre = statistics.median(a for a, _, _ in v)
            scale = statistics.median(b for _, b, _ in v)
            far = sum(a > far_px for a, _, _ in v) / len(v)
            runs = {}
            for _, _, name in v:
                runs[name] = runs.get(name, 0) + 1
            top = sorted(runs.items(), key=lambda kv: (-kv[1], kv[0]))[:3]
            most = ", ".join(f"`{n}` {k}" for n, k in top)
            lines.append(
                f"| {mode} | {r} | {len(v)} ({len(v) * frame_s:.2f} s) | {centre:.1f} | "
                f"{100 * far:.0f} % | {100 * scale:.1f} % | {most} |"
            )
    return "\n".join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("runs", nargs="+", help="run folders, each with a frames.csv")
    p.add_argument("--far-px", type=float, default=3.0, help="a centre error counted far")
    a = p.parse_args(argv)
    for d in a.runs:
        if not os.path.isfile(os.path.join(d, "frames.csv")):
            sys.exit(f"error: {d}: no frames.csv")
    print(table(classify(a.runs), a.far_px))


if __name__ == "__main__":
    main()
