#!/usr/bin/env python3
"""How far ahead the search first holds the lead in fog and in the dark: the report.

Reads the four sweeps that `examples/weather/acquisition.sh` makes of
`scenarios/sweeps/weather-acquisition.toml` (`day`, `dusk`, `night-low`, `night-high` under
one folder, each with its `results.jsonl`) and writes a Markdown report: for each light and
visual range, per tracker mode, the true range at which the tracker first held the lead
(`summary.json`'s `acquisition.range_m`; "never" when it did not in the run's 40 s), and
the chase's contact with it (`traffic.impact_speed_kph`), both seeds.

Usage: python3 examples/weather/acquisition.py renders/sweeps/weather-acquisition
       --out examples/weather/acquisition.md

Only the standard library.
"""

import argparse
import json
import os
import sys

# The study's lights, as its report names them (this folder is on the path when run); the
# acquisition runs in those without street lights (acquisition.sh).
from report import LIGHT_NAMES, LIGHTS

LIGHTS = [light for light in LIGHTS if light != "night-lit"]

MODES = ["paper", "robust"]


def results(path, script):
    """The runs of a sweep's `results.jsonl`: [(scenario, seed, params, summary)]; a missing
    file says to run `script`."""
    if not os.path.exists(path):
        sys.exit(f"error: {path}: missing (run examples/weather/{script})")
    out = []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            r = json.loads(line)
            s = r.get("summary")
            if s is None:
                sys.exit(f"error: {path}:{n}: point {r.get('point')} did not run")
            out.append((r["scenario"], r["seed"], r["params"], s))
    return out


def first_hold(summary):
    """A run's true range at its first hold and its impact speed (each None if none)."""
    acquired = (summary.get("acquisition") or {}).get("range_m")
    impact = (summary.get("traffic") or {}).get("impact_speed_kph")
    return acquired, impact


def read(folder):
    """The runs of the four lights: {(light, visual range, mode): [(seed, range, impact)]}."""
    runs = {}
    for light in LIGHTS:
        path = os.path.join(folder, light, "results.jsonl")
        for _, seed, p, s in results(path, "acquisition.sh"):
            key = (light, p["environment.fog.visual_range_m"], p["tracker.mode"])
            runs.setdefault(key, []).append((seed, *first_hold(s)))
    return runs


def cell(runs):
    """One table cell: each seed's first hold, and its contact if any."""
    out = []
    for _, acquired, impact in sorted(runs):
        text = "never" if acquired is None else f"{acquired:.1f} m"
        if impact is not None:
            text += f" (contact {impact:.0f} km/h)"
        out.append(text)
    return " / ".join(out)


def report(runs):
    """The Markdown report."""
    ranges = sorted({k[1] for k in runs}, reverse=True)
    lines = [
        "# How far ahead the search first holds the lead, in fog and in the dark",
        "",
        "Made by `examples/weather/acquisition.sh` (`scenarios/sweeps/weather-acquisition.toml`:",
        "`far-lead`, the chase closing from 150 m at 50 km/h on a lead at 20 km/h, its tracker",
        "searching from the start). Each cell: the true range at which the tracker first held",
        "the lead, seed 1 / seed 2, and the contact with it if any; *never*: not in the run's",
        "40 s.",
        "",
    ]
    for light in LIGHTS:
        lines += [f"## {LIGHT_NAMES[light]}", ""]
        lines += ["| visual range | paper's mode | robust mode |", "|---|---|---|"]
        for v in ranges:
            name = "clear" if v >= 10000 else f"{v:g} m"
            cells = [cell(runs.get((light, v, m), [])) for m in MODES]
            lines.append(f"| {name} | {cells[0]} | {cells[1]} |")
        lines.append("")
    return "\n".join(lines)


def cli(doc, folder_help, make):
    """A report's command line, FOLDER --out FILE: writes `make(FOLDER)`, the Markdown."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("folder", help=folder_help)
    parser.add_argument("--out", required=True, help="the Markdown file to write")
    args = parser.parse_args()
    text = make(args.folder)
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(text + "\n")
    print(f"wrote {args.out}")


def main():
    cli(__doc__, "the folder of the four lights' sweeps", lambda folder: report(read(folder)))


if __name__ == "__main__":
    main()
