#!/usr/bin/env python3
"""How far ahead the search first finds a vehicle standing in the lane: the report.

Reads the `results.jsonl` that `carfollow sweep scenarios/sweeps/car-acquisition.toml`
writes and writes a Markdown report: for each lens, kind and paint, per tracker mode, the
true range at which the tracker first held the standing vehicle (`summary.json`'s
`acquisition.range_m`, seed 1 / seed 2; "never" when it did not in the run's 30 s) and the
chase's impact speed when it hit it (`traffic.impact_speed_kph`); then, per lens and mode,
how many runs stopped short and how many never held the vehicle.

Usage: python3 examples/car-acquisition/report.py renders/sweeps/car-acquisition/results.jsonl
       --out examples/car-acquisition/report.md

Only the standard library.
"""

import argparse
import json
import sys

KINDS = ["sedan", "hatchback", "van", "truck"]
MODES = ["paper", "robust"]
ASPHALT_ALBEDO = 0.30


def read(path):
    """{(lens, kind, albedo, mode, seed): summary} from a sweep's `results.jsonl`; a point
    that did not run stops the report, naming its line."""
    runs = {}
    try:
        f = open(path, encoding="utf-8")
    except OSError as e:
        sys.exit(f"error: {path}: {e.strerror} (run examples/car-acquisition/run.sh)")
    with f:
        for n, line in enumerate(f, 1):
            r = json.loads(line)
            s = r.get("summary")
            if s is None:
                sys.exit(f"error: {path}:{n}: point {r.get('point')} did not run")
            p = r["params"]
            key = (
                p["camera.focal_length_mm"],
                p["actors.0.kind"],
                p["actors.0.albedo"],
                p["tracker.mode"],
                r["seed"],
            )
            runs[key] = s
    return runs


def first_hold(summary):
    """The true range at the first hold, m, and the impact speed, km/h (each None if none)."""
    acquired = (summary.get("acquisition") or {}).get("range_m")
    impact = (summary.get("traffic") or {}).get("impact_speed_kph")
    return acquired, impact


def cell(runs, lens, kind, albedo, mode, seeds):
    """`24.9 m / never; hit at – / 50 km/h`-style text for one mode's seeds, in order."""
    ranges, hits = [], []
    for seed in seeds:
        s = runs.get((lens, kind, albedo, mode, seed))
        if s is None:
            ranges.append("–")
            hits.append("–")
            continue
        acquired, impact = first_hold(s)
        ranges.append("never" if acquired is None else f"{acquired:.1f} m")
        hits.append("–" if impact is None else f"{impact:.0f}")
    text = " / ".join(ranges)
    if any(h != "–" for h in hits):
        text += f"; hit at {' / '.join(hits)} km/h"
    return text


def report(runs):
    lenses = sorted({k[0] for k in runs})
    albedos = sorted({k[2] for k in runs})
    seeds = sorted({k[4] for k in runs})
    out = [
        "# How far ahead the search first finds a vehicle standing in the lane",
        "",
        "Made by `examples/car-acquisition/run.sh` (`scenarios/sweeps/car-acquisition.toml`:",
        "`stopped-car-ahead`, the chase cruising at 50 km/h with nothing tracked, a vehicle",
        "standing in its lane 150 m on, a van passing in the next lane). Each cell: the true",
        "range at which the tracker first held the standing vehicle, "
        + " / ".join(f"seed {s}" for s in seeds)
        + ", and the impact speeds where the chase hit it (– for none); *never*: not in the",
        "run's 30 s.",
        f"The asphalt's albedo is {ASPHALT_ALBEDO}.",
        "",
    ]
    for lens in lenses:
        out += [
            f"## {lens:g} mm lens",
            "",
            "| vehicle | paint (albedo) | paper's mode | robust mode |",
            "|---|---|---|---|",
        ]
        for kind in KINDS:
            for albedo in albedos:
                cells = [cell(runs, lens, kind, albedo, m, seeds) for m in MODES]
                out.append(f"| {kind} | {albedo:g} | {cells[0]} | {cells[1]} |")
        out.append("")
    out += [
        "## In all",
        "",
        "| lens | mode | runs | stopped short | never held the vehicle |",
        "|---|---|---|---|---|",
    ]
    for lens in lenses:
        for mode in MODES:
            mine = [s for k, s in runs.items() if k[0] == lens and k[3] == mode]
            holds = [first_hold(s) for s in mine]
            short = sum(1 for _, hit in holds if hit is None)
            never = sum(1 for got, _ in holds if got is None)
            out.append(f"| {lens:g} mm | {mode} | {len(mine)} | {short} | {never} |")
    out.append("")
    return "\n".join(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("results", help="the sweep's results.jsonl")
    parser.add_argument("--out", help="where to write the report (default: stdout)")
    args = parser.parse_args()
    text = report(read(args.results))
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
