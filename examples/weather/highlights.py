#!/usr/bin/env python3
"""What highlight protection changes at night on high beams: the report.

Reads what `examples/weather/highlights.sh` makes under one folder (`study-plain` and
`study`: the weather study's night on high beams without and with
`environment.sensor.auto_gain.max_clipped_share` at 1 %; `acquisition-plain` and
`acquisition`: `far-lead` on high beams without and with it) and writes a Markdown
report: per road and tracker mode, the seconds lost, the runs that lost more than 2 s, the
runs with a silent loss of more than 15 frames and the false alarms, without and with; and
the first hold in `far-lead`, without and with.

Usage: python3 examples/weather/highlights.py renders/sweeps/weather-highlights
       --out examples/weather/highlights.md

Only the standard library.
"""

import os

# The acquisition report's reading, cells and command line (this folder is on the path
# when run).
from acquisition import cell, cli, first_hold, results


def sweep(folder, name):
    """The runs of the sweep `name` under `folder` (as `results` reads them)."""
    return results(os.path.join(folder, name, "results.jsonl"), "highlights.sh")


def study(runs):
    """A study sweep's figures: {(road, mode): [(seconds lost, silent frames, false alarm)]}."""
    rows = {}
    for road, _, p, s in runs:
        rows.setdefault((road, p["tracker.mode"]), []).append(
            (s["tracking_lost_s"], s["silent_loss_frames"], s["false_alarm_s"])
        )
    return rows


def figures(runs):
    """Seconds lost, runs over 2 s lost, runs silent over 15 frames, false alarm seconds."""
    return (
        sum(r[0] for r in runs),
        sum(r[0] > 2.0 for r in runs),
        sum(r[1] > 15 for r in runs),
        sum(r[2] for r in runs),
    )


def first_holds(runs):
    """`far-lead`'s first holds: {(visual range, mode): "a / b"} over the seeds."""
    cells = {}
    for _, seed, p, s in runs:
        key = (p["environment.fog.visual_range_m"], p["tracker.mode"])
        cells.setdefault(key, []).append((seed, *first_hold(s)))
    return {k: cell(v) for k, v in cells.items()}


def report(folder):
    """The Markdown report."""
    without = study(sweep(folder, "study-plain"))
    with_ = study(sweep(folder, "study"))
    lines = [
        "# Highlight protection at night on high beams",
        "",
        "Made by `examples/weather/highlights.sh`: the automatic gain (up to 64) meters the",
        "frame's mean, without and with `environment.sensor.auto_gain.max_clipped_share = 0.01`",
        "(at most 1 % of the metering window let clip to white).",
        "",
        "## The weather study's night on high beams",
        "",
        "Sums over each road and mode's 48 runs (6 visual ranges × 4 rain rates × 2 seeds,",
        "30 s each).",
        "",
        "| road | mode | seconds lost | runs > 2 s lost | runs silent > 15 frames"
        " | false alarm, s |",
        "|---|---|---|---|---|---|",
    ]
    for key in sorted(with_):
        a, b = figures(without.get(key, [])), figures(with_[key])
        lines.append(
            f"| `{key[0]}` | {key[1]} | {a[0]:.1f} → {b[0]:.1f} | {a[1]} → {b[1]}"
            f" | {a[2]} → {b[2]} | {a[3]:.1f} → {b[3]:.1f} |"
        )
    plain = first_holds(sweep(folder, "acquisition-plain"))
    held = first_holds(sweep(folder, "acquisition"))
    lines += [
        "",
        "## First hold in `far-lead` on high beams",
        "",
        "The true range at which the tracker first held the lead, seed 1 / seed 2, and the",
        "contact if any; *never*: not in the run's 40 s.",
        "",
        "| visual range | mode | without | with |",
        "|---|---|---|---|",
    ]
    for v, mode in sorted(held, key=lambda k: (-k[0], k[1])):
        name = "clear" if v >= 10000 else f"{v:g} m"
        lines.append(f"| {name} | {mode} | {plain.get((v, mode), '')} | {held[(v, mode)]} |")
    return "\n".join(lines)


def main():
    cli(__doc__, "the folder highlights.sh wrote into", report)


if __name__ == "__main__":
    main()
