#!/usr/bin/env python3
"""The weather study's silent losses, looked into: what the tracker was holding while the
ground truth said the target was lost and the status said `tracking`, and whether any signal
the tracker already has would have told the two apart.

It runs (skipping runs already in OUT):
- `nist-grounds` at night on high beams, the grid where the study found its silent losses
  (visual range x rain x tracker mode x seeds 1 and 2, as `scenarios/sweeps/weather.toml`
  and `run.sh` set them), 96 runs of 30 s;
- every library scenario in `scenarios/` in both tracker modes, as shipped,
and then, over every frame whose status is `tracking`, reads `frames.csv`:
- the silent frames (`lost_truth` = 1), their runs, and what the estimate held there
  (its scale against the truth's, its centre's distance from the truth's);
- for each candidate check (floors on the eq. 17 confidences; the fit residual J_l against
  its own running reference; the estimate's scale jumping over three frames), the silent
  frames it would have caught and the frames it would
  have turned into false alarms (status not `tracking` with the estimate within the truth's
  tolerance), on the weather grid and on the library.

    python3 examples/weather/silent.py --carfollow ./target/release/carfollow \
        --out renders/silent
"""

import argparse
import csv
import math
import pathlib
import statistics
import subprocess

# The weather study's grid (scenarios/sweeps/weather.toml) and its night on high beams
# (examples/weather/run.sh).
GRID_SET = [
    "duration_s=30",
    "environment.sensor.auto_gain.max_gain=64",
    "expect.min_distance_m=100",
    "environment.sun.elevation_deg=-18",
    "chase.headlamps.beam=high",
]
VISUAL_RANGES_M = ["100000.0", "200.0", "100.0", "60.0", "40.0", "25.0"]
RAIN_MM_H = ["0.0", "2.0", "8.0", "25.0"]
MODES = ["paper", "robust"]
SEEDS = ["1", "2"]
# A loss the status does not report for longer than this is the silent loss.
SILENT_FRAMES = 15


def run(carfollow, scenario, sets, out):
    """Runs one scenario into `out` unless its frames are there already."""
    if (out / "frames.csv").exists():
        return
    cmd = [carfollow, "run", str(scenario), "--quiet", "--out", str(out)]
    for s in sets:
        cmd += ["--set", s]
    # Exit status 1 is a run whose criteria failed: its frames are what is wanted.
    status = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if status.returncode not in (0, 1):
        raise SystemExit(f"{' '.join(cmd)}: exit {status.returncode}: {status.stderr.strip()}")


def run_all(carfollow, root, out):
    """The weather grid's night on high beams, then the library in both modes."""
    for seed in SEEDS:
        for v in VISUAL_RANGES_M:
            for r in RAIN_MM_H:
                for m in MODES:
                    sets = GRID_SET + [
                        f"seed={seed}",
                        f"environment.fog.visual_range_m={v}",
                        f"environment.rain.rate_mm_h={r}",
                        f"tracker.mode={m}",
                    ]
                    name = f"seed{seed}-v{v}-rain{r}-{m}"
                    run(carfollow, root / "scenarios/nist-grounds.toml", sets, out / "grid" / name)
    for scenario in sorted((root / "scenarios").glob("*.toml")):
        for m in MODES:
            run(carfollow, scenario, [f"tracker.mode={m}"], out / "library" / f"{scenario.stem}-{m}")


def number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def tracking_frames(folder):
    """Per run, the frames whose status is `tracking`, in order."""
    runs = {}
    for f in sorted(folder.glob("*/frames.csv")):
        with open(f, newline="") as handle:
            runs[f.parent.name] = [r for r in csv.DictReader(handle) if r["status"] == "tracking"]
    return runs


def confidence_floor(floor):
    def check(rows):
        return [
            number(r["confidence_x"]) < floor or number(r["confidence_scale"]) < floor
            for r in rows
        ]

    return check


def residual_ratio(ratio, gain=0.05, warm_up=5):
    """J_l over `ratio` times its running mean over the frames this check passed."""

    def check(rows):
        flags, reference, taken = [], None, 0
        for r in rows:
            j = number(r["fit_residual"])
            bad = reference is not None and taken >= warm_up and not j <= ratio * reference
            flags.append(bad)
            if not bad and math.isfinite(j):
                reference = j if reference is None else reference + gain * (j - reference)
                taken += 1
        return flags

    return check


def scale_jump(log_ratio, frames=3):
    """The estimate's scale changed by more than `log_ratio` (natural log) over `frames`
    frames: a range that jumps faster than the lead and the chase move apart or together."""

    def check(rows):
        flags = []
        for k, r in enumerate(rows):
            if k < frames:
                flags.append(False)
                continue
            now, before = number(r["est_scale"]), number(rows[k - frames]["est_scale"])
            ok = now > 0 and before > 0 and math.isfinite(now) and math.isfinite(before)
            flags.append(ok and abs(math.log(now / before)) > log_ratio)
        return flags

    return check


def weigh(runs, check):
    """Silent frames caught, and frames made false alarms (with their runs), by `check`."""
    caught = alarms = alarm_runs = 0
    for rows in runs.values():
        flags = check(rows)
        new = 0
        for r, bad in zip(rows, flags):
            if bad and r["lost_truth"] == "1":
                caught += 1
            elif bad:
                new += 1
        alarms += new
        alarm_runs += new > 0
    return caught, alarms, alarm_runs


def describe(name, runs):
    silent = {k: [r for r in rows if r["lost_truth"] == "1"] for k, rows in runs.items()}
    total = sum(len(v) for v in silent.values())
    frames = sum(len(v) for v in runs.values())
    long = sorted((len(v), k) for k, v in silent.items() if len(v) > SILENT_FRAMES)
    print(f"## {name}: {len(runs)} runs, {frames} frames `tracking`, {total} of them silent")
    print(f"runs with more than {SILENT_FRAMES} silent frames: {len(long)}")
    for n, k in reversed(long):
        rows = silent[k]
        ratio = statistics.median(
            number(r["est_scale"]) / number(r["true_scale"]) for r in rows
        )
        centre = statistics.median(
            math.hypot(
                number(r["est_cx_px"]) - number(r["true_cx_px"]),
                number(r["est_cy_px"]) - number(r["true_cy_px"]),
            )
            for r in rows
        )
        print(f"  {k}: {n} frames, scale {ratio:.2f}x the truth's, centre {centre:.1f} px off (medians)")
    return total


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--carfollow", default="carfollow")
    parser.add_argument("--out", default="renders/silent", type=pathlib.Path)
    parser.add_argument("--root", default=".", type=pathlib.Path, help="the checkout")
    args = parser.parse_args()
    run_all(args.carfollow, args.root, args.out)
    grid = tracking_frames(args.out / "grid")
    library = tracking_frames(args.out / "library")
    silent_grid = describe("nist-grounds at night on high beams", grid)
    silent_library = describe("the library, both modes", library)
    checks = [(f"confidence x or scale < {f}", confidence_floor(f)) for f in (0.8, 1.0, 1.2)]
    checks += [(f"J_l > {k} x its reference", residual_ratio(k)) for k in (4, 6, 10)]
    checks += [(f"scale changed by more than {j} (log) over 3 frames", scale_jump(j))
               for j in (0.1, 0.2, 0.3)]
    print("\n| check | grid: silent caught | grid: new false alarms (runs) "
          "| library: silent caught | library: new false alarms (runs) |")
    print("|---|---|---|---|---|")
    for name, check in checks:
        gc, ga, gr = weigh(grid, check)
        lc, la, lr = weigh(library, check)
        print(f"| {name} | {gc} of {silent_grid} | {ga} ({gr}) | {lc} of {silent_library} | {la} ({lr}) |")


if __name__ == "__main__":
    main()
